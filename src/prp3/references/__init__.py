"""The independent routes: the paper's recursive matrix method as printed (`paper_kinematics`, `paper_wrenches`, `paper`) and Newton-Euler of the seven bodies (`newton_euler`)."""
