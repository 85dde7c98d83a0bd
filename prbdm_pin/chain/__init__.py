"""Chain kernels.

The rigid links of a member cut at the joint stations (exact mass, centre of mass and inertia), the
springs, the closed-form planar chain vectorised over designs and poses, the generalised
eigensolver, Pinocchio's CRBA and kinematics, large-deflection statics; each derivative module
(``*_derivatives``) beside the primal it differentiates.
"""
