"""The PRBDM as a Pinocchio model.

The URDF rendered from the templates, `PrbdmModel` and `build_model`, the support (a clamped root or
a hub), and the model's inputs and outputs.
"""
