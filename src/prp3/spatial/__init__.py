"""Spatial parallel robots: legs of R, P, U, S joints between a fixed base and a platform.

The model of ``docs/spatial.md``: a robot is legs of placed joints (the joint
types written once, generically), with the bodies between them; the modules
follow the data flow ``model → geometry → kinematics → dynamics``
(:mod:`~prp3.spatial.model`, :mod:`~prp3.spatial.geometry`,
:mod:`~prp3.spatial.kinematics`, :mod:`~prp3.spatial.dynamics` and the
independent :mod:`~prp3.spatial.newton_euler`).  The first robot is the 6-UPS
Stewart–Gough hexapod (:func:`~prp3.spatial.model.hexapod`).
"""
