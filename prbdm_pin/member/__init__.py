"""The compliant member.

Its material, its planform and thickness (`Beam`), the field checks, random members (the paper's
Sec. 2.1) and the design variables an optimiser moves.
"""
