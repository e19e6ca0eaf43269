"""The spatial robots' inverse dynamics as C99 code (``prp3 export c`` of a spatial robot file).

:func:`spatial_c_inverse_dynamics` writes a C99 header and source computing, for one
robot of docs/spatial.md (6-UPS hexapod, 3-RPS, Delta as 3-RUU), the joint motion,
the actuator efforts and the wrench of every joint from the platform's pose, twist and
its derivative (docs/spatial.md §4, §9, §24)::

    int prp3_inverse_dynamics(const double position[3], const double rotation[9],
                              const double omega[3], const double velocity[3],
                              const double alpha[3], const double acceleration[3],
                              double q[PRP3_LEGS * PRP3_DOF], double dq[PRP3_LEGS * PRP3_DOF],
                              double ddq[PRP3_LEGS * PRP3_DOF], double tau[PRP3_LEGS],
                              double force[PRP3_LEGS * PRP3_JOINTS * 3],
                              double moment[PRP3_LEGS * PRP3_JOINTS * 3]);

``rotation`` is ``R`` row by row; ``q[dof·i + c]`` the coordinate ``c`` of leg ``i``;
``force[3·(3·i + k) + r]`` and ``moment[…]`` the component ``r`` (world frame) of the
wrench of joint ``k``'s proximal body on its distal body at the joint point, as
:func:`~prp3.spatial.outputs.spatial_inverse_dynamics` gives them.  The return codes
are :data:`prp3.spatial.compiled.SPATIAL_STATUS` (whose first six are the planar C's,
:data:`prp3.apps.codegen.RETURN_CODES`), each ``#define``'d and explained once in the
header; one ``isfinite`` pass over every output at the end, so the code never returns
``PRP3_OK`` with a non-finite output, and on a non-zero return every output is NaN.

How it is written: the steps are those of the compiled kernel
(:mod:`prp3.spatial.compiled`, itself the numpy route of
:func:`~prp3.spatial.newton_euler.recursive_newton_euler` on scalars) — the closed-form
leg geometry of §5 on its branch, the limits of §6, the leg Jacobians and the measures
refused below ``1e-4`` times their sign at home, ``dq``, ``ddq`` by the chain's
recursion, the leg bodies' balances from the platform inwards, one ``6 × 6`` solve for
``(τ, λ)`` and every joint wrench — as one fixed C text (:data:`KERNEL`, LU with partial
pivoting as the kernel's); the robot is data: its pattern, leg count and joint kinds
are ``#define``'d (the compiler folds the branches and unrolls the loops) and its
placements, bodies, limits and home signs are one ``static const double PAR[]`` in the
layout of :data:`PACKED`.  Only ``<math.h>``; strict C99.

>>> from prp3.spatial.model import hexapod
>>> code = spatial_c_inverse_dynamics(hexapod())
>>> "#define PRP3_LEGS 6" in code.header, "#define PRP3_NOT_A_POSE 8" in code.header
(True, True)
>>> "M_PI" in code.source, code.source.count("#include")
(False, 2)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from prp3.apps.codegen import HEADER_NAME, SOURCE_NAME, version
from prp3.spatial.compiled import SPATIAL_STATUS
from prp3.spatial.geometry import PLANE_TOLERANCE
from prp3.spatial.kinematics import COMPATIBILITY, SINGULAR, home_signs
from prp3.spatial.model import ORTHONORMAL_TOLERANCE, SpatialRobot
from prp3.validation import check_instance

__all__ = [
    "KERNEL",
    "PACKED",
    "SpatialCSource",
    "spatial_c_inverse_dynamics",
    "spatial_packed",
]

#: The C kernel's pattern numbers and joint kinds.
_PATTERNS = {"UPS": 0, "RPS": 1, "RUU": 2}
_KINDS = {"R": 0, "P": 1, "U": 2, "S": 3}

#: The layout of ``PAR``: each block's name and its size for ``L`` legs of 3 joints
#: (placements, attachments, the leg bodies, the platform, gravity, the robot's length,
#: the limits of every coordinate, the signs of the measures at home, the closure tolerance).
PACKED: tuple[tuple[str, str], ...] = (
    ("JPOS", "legs x joints x 3: joint placements in the proximal body"),
    ("JROT", "legs x joints x 9: their rotations, row by row"),
    ("APOS", "legs x 3: the leg's end in the platform"),
    ("AROT", "legs x 9: its rotation"),
    ("BMASS", "legs x 2: the leg bodies' masses"),
    ("BCEN", "legs x 2 x 3: their mass centres"),
    ("BINE", "legs x 2 x 9: their inertias about the centre (body frame)"),
    ("PMASS", "1: the platform's mass"),
    ("PCEN", "3: its mass centre"),
    ("PINE", "9: its inertia"),
    ("GRAV", "3: gravity"),
    ("SCALE", "1: the robot's length l"),
    ("LIMITS", "legs x joints x 3 x 2: the coordinates' limits (an S joint: its angle)"),
    ("LEGSIGN", "legs: the sign of mu_leg at home"),
    ("PARSIGN", "1: the sign of mu_par at home"),
    ("PLANE", "1: the closure tolerance of a leg of 5 coordinates, PLANE_TOLERANCE l"),
)


@dataclass(frozen=True)
class SpatialCSource:
    """The generated C code of a spatial robot.

    Attributes
    ----------
    header, source : str
        Texts of ``prp3_inverse_dynamics.h`` and ``.c``.
    robot : SpatialRobot
    """

    header: str
    source: str
    robot: SpatialRobot


def spatial_packed(robot: SpatialRobot) -> tuple[dict[str, int], list[float]]:
    """The robot as the C's ``PAR``: the offset of each block of :data:`PACKED`, and the values.

    Raises
    ------
    ParameterError
        ``robot`` is not a :class:`~prp3.spatial.model.SpatialRobot`.
    """
    robot = check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    legs = robot.legs
    blocks: dict[str, list[float]] = {name: [] for name, _ in PACKED}
    for leg in legs:
        for joint in leg.joints:
            blocks["JPOS"] += [float(v) for v in joint.position]
            blocks["JROT"] += [float(v) for row in joint.rotation for v in row]
            pairs = [(float(lo), float(hi)) for lo, hi in joint.limits]
            pairs += [(-math.inf, math.inf)] * (3 - len(pairs))
            blocks["LIMITS"] += [v for pair in pairs for v in pair]
        blocks["APOS"] += [float(v) for v in leg.attachment_position]
        blocks["AROT"] += [float(v) for row in leg.attachment_rotation for v in row]
        for body in leg.bodies:
            blocks["BMASS"].append(float(body.mass))
            blocks["BCEN"] += [float(v) for v in body.centre]
            blocks["BINE"] += [float(v) for row in body.inertia for v in row]
    platform = robot.platform
    blocks["PMASS"] = [float(platform.mass)]
    blocks["PCEN"] = [float(v) for v in platform.centre]
    blocks["PINE"] = [float(v) for row in platform.inertia for v in row]
    blocks["GRAV"] = [float(v) for v in robot.gravity]
    blocks["SCALE"] = [float(robot.scale)]
    leg_sign, par_sign = home_signs(robot)
    blocks["LEGSIGN"] = [float(v) for v in leg_sign]
    blocks["PARSIGN"] = [float(par_sign)]
    blocks["PLANE"] = [PLANE_TOLERANCE * float(robot.scale)]
    offsets: dict[str, int] = {}
    values: list[float] = []
    for name, _ in PACKED:
        offsets[name] = len(values)
        values += blocks[name]
    return offsets, values


def _number(value: float) -> str:
    """A double as C text that reads back exactly; the infinities as ``HUGE_VAL``."""
    if math.isinf(value):
        return "HUGE_VAL" if value > 0 else "-HUGE_VAL"
    if math.isnan(value):  # pragma: no cover - a validated robot has no NaN
        raise AssertionError("a constant of the C code is NaN")
    text = repr(float(value))
    return text if any(ch in text for ch in ".en") else text + ".0"


def _robot_line(robot: SpatialRobot) -> str:
    leg = robot.legs[0]
    return (
        f"{robot.name}, {len(robot.legs)} {leg.pattern} legs ({leg.dof} coordinates, actuated "
        f"{leg.coordinates[leg.actuated_coordinate]}), platform mass {robot.platform.mass!r} kg, "
        f"gravity {list(robot.gravity)!r} m/s^2"
    )


def _prelude(robot: SpatialRobot) -> list[str]:
    """The robot's ``#define``'s and constants before :data:`KERNEL`."""
    leg = robot.legs[0]
    offsets, values = spatial_packed(robot)
    kinds = ", ".join(str(_KINDS[joint.kind]) for joint in leg.joints)
    rows = [", ".join(_number(v) for v in values[k : k + 4]) for k in range(0, len(values), 4)]
    return [
        f"#define PRP3_PATTERN {_PATTERNS[leg.pattern]} /* 0 UPS, 1 RPS, 2 RUU */",
        f"#define PRP3_ACTUATED {leg.actuated_coordinate} /* the actuated coordinate */",
        f"#define PRP3_S_CLOSED {int(leg.dof >= 5 and leg.joints[-1].kind == 'S')}"
        " /* 1: legs closed by an S joint, J = [[A, 1], [B, 0]] */",
        "#define PRP3_ONE_PASS 1 /* 1: the chain's motion once (q'' = 0), the q'' terms added;"
        " 0: twice */",
        f"static const int KIND[3] = {{{kinds}}}; /* the joints: 0 R, 1 P, 2 U, 3 S */",
        f"static const double PRP3_SINGULARITY_THRESHOLD = {_number(SINGULAR)};",
        f"static const double PRP3_COMPATIBILITY = {_number(COMPATIBILITY)};",
        f"static const double PRP3_ORTHONORMAL = {_number(ORTHONORMAL_TOLERANCE)};",
        "",
        "/* the robot's placements, bodies, limits and home signs (the blocks below) */",
        *(f"#define {name} {offsets[name]} /* {what} */" for name, what in PACKED),
        f"static const double PAR[{len(values)}] = {{",
        *(f"    {row}," for row in rows),
        "};",
    ]


def _header(robot: SpatialRobot) -> str:
    leg = robot.legs[0]
    legs, dof, joints = len(robot.legs), leg.dof, len(leg.joints)
    kind = "N" if leg.joints[leg.actuated].kind == "P" else "N m"
    lines = [
        f"/* {HEADER_NAME}: inverse dynamics of the {robot.name} spatial parallel robot (C99).",
        f" * Generated by prp3 {version()} (prp3 export c). Robot: {_robot_line(robot)}",
        " *",
        " * prp3_inverse_dynamics(position, rotation, omega, velocity, alpha, acceleration,",
        " *                       q, dq, ddq, tau, force, moment)",
        " *   position: the platform frame's origin p (m, world frame); rotation: its matrix R",
        " *   row by row (orthonormal to 1e-9); omega, velocity: its angular velocity (rad/s)",
        " *   and dp/dt (m/s); alpha, acceleration: their derivatives (docs/spatial.md sec. 4).",
        f" *   q, dq, ddq[{dof} i + c]: coordinate c = "
        + ", ".join(leg.coordinates)
        + " of leg i (rad, m and their rates);",
        f" *   tau[i]: the effort of leg i's actuator ({kind});",
        " *   force, moment[3 (3 i + k) + r]: component r (world frame) of the wrench that joint",
        " *   k's proximal body exerts on its distal body, at the joint point (N, N m); joints "
        + ", ".join(leg.labels)
        + ".",
        " * Returns one of the codes below: PRP3_OK (0) only when every output is finite.",
        " * On a non-zero return every output is NaN. Reentrant, no allocation, only",
        " * <math.h>. Do not compile with -ffast-math: it assumes no NaN and removes the checks.",
        " */",
        "#ifndef PRP3_INVERSE_DYNAMICS_H",
        "#define PRP3_INVERSE_DYNAMICS_H",
        "",
        f"#define PRP3_LEGS {legs} /* legs */",
        f"#define PRP3_DOF {dof} /* coordinates per leg */",
        f"#define PRP3_JOINTS {joints} /* joints per leg */",
        "",
        "/* the return codes of prp3_inverse_dynamics, one per kind of failure */",
        *(f"#define {name} {value} /* {meaning} */" for name, value, meaning in SPATIAL_STATUS),
        "",
        "#ifdef __cplusplus",
        'extern "C" {',
        "#endif",
        "",
        *_SIGNATURE[:-1],
        _SIGNATURE[-1] + ";",
        "",
        "#ifdef __cplusplus",
        "}",
        "#endif",
        "",
        "#endif /* PRP3_INVERSE_DYNAMICS_H */",
    ]
    return "\n".join(lines) + "\n"


def spatial_c_inverse_dynamics(robot: SpatialRobot) -> SpatialCSource:
    """Generate the C99 header and source of the inverse dynamics of a spatial robot.

    Parameters
    ----------
    robot : SpatialRobot
        Its joint placements, bodies, gravity, limits and home signs become constants of
        the source (docs/spatial.md §24).

    Returns
    -------
    SpatialCSource

    Raises
    ------
    ParameterError
        ``robot`` is not a :class:`~prp3.spatial.model.SpatialRobot`.
    """
    robot = check_instance("robot", robot, SpatialRobot, "a SpatialRobot")
    lines = [
        f"/* {SOURCE_NAME}: inverse dynamics of the {robot.name} spatial parallel robot.",
        f" * Generated by prp3 {version()} (prp3 export c): the steps of prp3's compiled",
        " * kernel (docs/spatial.md sec. 19, 24), the robot as constants. Do not edit: regenerate.",
        f" * Robot: {_robot_line(robot)} */",
        "#include <math.h>",
        f'#include "{HEADER_NAME}"',
        "",
        *_prelude(robot),
        KERNEL,
    ]
    source = "\n".join(lines)
    return SpatialCSource(header=_header(robot), source=source, robot=robot)


_SIGNATURE = (
    "int prp3_inverse_dynamics(const double position[3], const double rotation[9],",
    "                          const double omega[3], const double velocity[3],",
    "                          const double alpha[3], const double acceleration[3],",
    "                          double q[PRP3_LEGS * PRP3_DOF], double dq[PRP3_LEGS * PRP3_DOF],",
    "                          double ddq[PRP3_LEGS * PRP3_DOF], double tau[PRP3_LEGS],",
    "                          double force[PRP3_LEGS * PRP3_JOINTS * 3],",
    "                          double moment[PRP3_LEGS * PRP3_JOINTS * 3])",
)

#: The C text of the steps (after the robot's constants of the source's prelude).
KERNEL: str = r"""
/* ---- generic numerics (packed robot in PAR, sizes and kinds above) ---- */
#define NJ 3
#define Q(a, i, c) ((a)[(i) * PRP3_DOF + (c)])

static const int KDOF[4] = {1, 1, 2, 3};

static void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* LU with partial pivoting of a[:n][:n] in place; the determinant */
static double lu(double a[6][6], int n, int piv[6])
{
    double det = 1.0;
    int k, r, c;
    for (k = 0; k < n; ++k) {
        int p = k;
        double big = fabs(a[k][k]);
        double d;
        for (r = k + 1; r < n; ++r) {
            if (fabs(a[r][k]) > big) {
                big = fabs(a[r][k]);
                p = r;
            }
        }
        piv[k] = p;
        if (p != k) {
            det = -det;
            for (c = 0; c < n; ++c) {
                double t = a[k][c];
                a[k][c] = a[p][c];
                a[p][c] = t;
            }
        }
        d = a[k][k];
        det *= d;
        if (d == 0.0) {
            continue;
        }
        for (r = k + 1; r < n; ++r) {
            double f = a[r][k] / d;
            a[r][k] = f;
            for (c = k + 1; c < n; ++c) {
                a[r][c] -= f * a[k][c];
            }
        }
    }
    return det;
}

static void lu_solve(double a[6][6], int n, const int piv[6], double b[6])
{
    int k, r, c;
    for (k = 0; k < n; ++k) {
        int p = piv[k];
        if (p != k) {
            double t = b[k];
            b[k] = b[p];
            b[p] = t;
        }
    }
    for (r = 1; r < n; ++r) {
        double s = b[r];
        for (c = 0; c < r; ++c) {
            s -= a[r][c] * b[c];
        }
        b[r] = s;
    }
    for (r = n - 1; r >= 0; --r) {
        double s = b[r];
        for (c = r + 1; c < n; ++c) {
            s -= a[r][c] * b[c];
        }
        b[r] = s / a[r][r];
    }
}

static void lu_solve_transposed(double a[6][6], int n, const int piv[6], double b[6])
{
    int k, r, c;
    for (r = 0; r < n; ++r) {
        double s = b[r];
        for (c = 0; c < r; ++c) {
            s -= a[c][r] * b[c];
        }
        b[r] = s / a[r][r];
    }
    for (r = n - 1; r >= 0; --r) {
        double s = b[r];
        for (c = r + 1; c < n; ++c) {
            s -= a[c][r] * b[c];
        }
        b[r] = s;
    }
    for (k = n - 1; k >= 0; --k) {
        int p = piv[k];
        if (p != k) {
            double t = b[k];
            b[k] = b[p];
            b[p] = t;
        }
    }
}

/* out = m Rot_z(angle), m Rot_y(angle) */
static void rot_z(double m[3][3], double angle, double out[3][3])
{
    const double c = cos(angle), s = sin(angle);
    int r;
    for (r = 0; r < 3; ++r) {
        const double x = m[r][0], y = m[r][1];
        out[r][0] = x * c + y * s;
        out[r][1] = -x * s + y * c;
        out[r][2] = m[r][2];
    }
}

static void rot_y(double m[3][3], double angle, double out[3][3])
{
    const double c = cos(angle), s = sin(angle);
    int r;
    for (r = 0; r < 3; ++r) {
        const double x = m[r][0], z = m[r][2];
        out[r][0] = x * c - z * s;
        out[r][1] = m[r][1];
        out[r][2] = x * s + z * c;
    }
}

#if PRP3_PATTERN != 2
/* the principal rotation vector of r through its quaternion (Shepperd) */
static void rot_log(double r[3][3], double out[3])
{
    const double trace = r[0][0] + r[1][1] + r[2][2];
    double best = trace, s, w, x, y, z, norm, sv, scale;
    int pick = 0;
    if (r[0][0] > best) {
        pick = 1;
        best = r[0][0];
    }
    if (r[1][1] > best) {
        pick = 2;
        best = r[1][1];
    }
    if (r[2][2] > best) {
        pick = 3;
    }
    if (pick == 0) {
        s = sqrt(fmax(1.0 + trace, 0.0)) * 2.0;
        w = s / 4.0;
        x = (r[2][1] - r[1][2]) / s;
        y = (r[0][2] - r[2][0]) / s;
        z = (r[1][0] - r[0][1]) / s;
    } else if (pick == 1) {
        s = sqrt(fmax(1.0 + r[0][0] - r[1][1] - r[2][2], 0.0)) * 2.0;
        w = (r[2][1] - r[1][2]) / s;
        x = s / 4.0;
        y = (r[0][1] + r[1][0]) / s;
        z = (r[0][2] + r[2][0]) / s;
    } else if (pick == 2) {
        s = sqrt(fmax(1.0 - r[0][0] + r[1][1] - r[2][2], 0.0)) * 2.0;
        w = (r[0][2] - r[2][0]) / s;
        x = (r[0][1] + r[1][0]) / s;
        y = s / 4.0;
        z = (r[1][2] + r[2][1]) / s;
    } else {
        s = sqrt(fmax(1.0 - r[0][0] - r[1][1] + r[2][2], 0.0)) * 2.0;
        w = (r[1][0] - r[0][1]) / s;
        x = (r[0][2] + r[2][0]) / s;
        y = (r[1][2] + r[2][1]) / s;
        z = s / 4.0;
    }
    norm = sqrt(w * w + x * x + y * y + z * z);
    if (w < 0.0) {
        norm = -norm;
    }
    w /= norm;
    x /= norm;
    y /= norm;
    z /= norm;
    sv = sqrt(x * x + y * y + z * z);
    if (sv < 1e-12) {
        scale = 2.0 / (w == 0.0 ? 1.0 : w);
    } else {
        scale = 2.0 * atan2(sv, w) / sv;
    }
    out[0] = scale * x;
    out[1] = scale * y;
    out[2] = scale * z;
}
#endif

/* the frames of the chain of a leg */
typedef struct {
    double jo[PRP3_LEGS][NJ][3];      /* joint origins */
    double fo[PRP3_LEGS][NJ][3];      /* frame origins (after the joint's motion) */
    double jr[PRP3_LEGS][NJ][3][3];   /* joint frames */
    double fr[PRP3_LEGS][NJ][3][3];   /* the distal body's frame */
    double axes[PRP3_LEGS][6][3];     /* the coordinates' axes (world) */
} Frames;

static void chain(int i, const double q[], Frames *f)
{
    double o[3] = {0.0, 0.0, 0.0};
    double rot[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
    double cross_frame[3][3];
    int col = 0, k, r, c, a;
    for (k = 0; k < NJ; ++k) {
        const int kind = KIND[k];
        const double *pos = &PAR[JPOS + 3 * (NJ * i + k)];
        const double *pr = &PAR[JROT + 9 * (NJ * i + k)];
        for (r = 0; r < 3; ++r) {
            f->jo[i][k][r] = o[r] + rot[r][0] * pos[0] + rot[r][1] * pos[1] + rot[r][2] * pos[2];
            for (c = 0; c < 3; ++c) {
                f->jr[i][k][r][c] = rot[r][0] * pr[c] + rot[r][1] * pr[3 + c] + rot[r][2] * pr[6 + c];
            }
        }
        if (kind == 0) { /* R */
            for (r = 0; r < 3; ++r) {
                f->axes[i][col][r] = f->jr[i][k][r][2];
                f->fo[i][k][r] = f->jo[i][k][r];
            }
            rot_z(f->jr[i][k], Q(q, i, col), f->fr[i][k]);
        } else if (kind == 1) { /* P */
            for (r = 0; r < 3; ++r) {
                f->axes[i][col][r] = f->jr[i][k][r][0];
                f->fo[i][k][r] = f->jo[i][k][r] + Q(q, i, col) * f->jr[i][k][r][0];
                for (c = 0; c < 3; ++c) {
                    f->fr[i][k][r][c] = f->jr[i][k][r][c];
                }
            }
        } else if (kind == 2) { /* U */
            rot_z(f->jr[i][k], Q(q, i, col), cross_frame);
            for (r = 0; r < 3; ++r) {
                f->axes[i][col][r] = f->jr[i][k][r][2];
                f->axes[i][col + 1][r] = cross_frame[r][1];
                f->fo[i][k][r] = f->jo[i][k][r];
            }
            rot_y(cross_frame, Q(q, i, col + 1), f->fr[i][k]);
        } else { /* S, the last joint: world axes; its distal frame is the platform's */
            for (a = 0; a < 3; ++a) {
                for (r = 0; r < 3; ++r) {
                    f->axes[i][col + a][r] = a == r ? 1.0 : 0.0;
                }
            }
            for (r = 0; r < 3; ++r) {
                f->fo[i][k][r] = f->jo[i][k][r];
            }
            return;
        }
        col += KDOF[kind];
        for (r = 0; r < 3; ++r) {
            o[r] = f->fo[i][k][r];
            for (c = 0; c < 3; ++c) {
                rot[r][c] = f->fr[i][k][r][c];
            }
        }
    }
}

#if PRP3_PATTERN == 2
/* the U angles (a, b) of the direction (x, y, z), cos b > 0 */
static void angles(double x, double y, double z, double *a, double *b)
{
    *a = atan2(y, x);
    *b = atan2(-z, hypot(x, y));
}
#endif

/* m = jr[i][2]^T re */
static void relative(const Frames *f, int i, double re[3][3], double m[3][3])
{
    int r, c;
    for (r = 0; r < 3; ++r) {
        for (c = 0; c < 3; ++c) {
            m[r][c] = f->jr[i][2][0][r] * re[0][c] + f->jr[i][2][1][r] * re[1][c]
                      + f->jr[i][2][2][r] * re[2][c];
        }
    }
}

/* the limits of leg i (the first code kept) */
static int limits(int i, const double q[], int status)
{
    int col = 0, k, c;
    for (k = 0; k < NJ; ++k) {
        const int kind = KIND[k];
        const double *lim = &PAR[LIMITS + 2 * 3 * (NJ * i + k)];
        if (kind == 3) {
            const double *s = &Q(q, i, col);
            const double angle = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
            if (angle < lim[0] || angle > lim[1]) {
                status = status == PRP3_OK ? PRP3_JOINT_LIMIT : status;
            }
        } else {
            for (c = 0; c < KDOF[kind]; ++c) {
                const double v = Q(q, i, col + c);
                if (v < lim[2 * c] || v > lim[2 * c + 1]) {
                    const int code = kind == 1 ? PRP3_OUTSIDE_STROKE : PRP3_JOINT_LIMIT;
                    status = status == PRP3_OK ? code : status;
                }
            }
        }
        col += KDOF[kind];
    }
    return status;
}

/* every leg's closed-form inverse geometry on its branch, limits checked */
static int geometry(const double p[3], double rm[3][3], double q[], Frames *f)
{
    int status = PRP3_OK, i, r, c;
    for (i = 0; i < PRP3_LEGS; ++i) {
        const double *ap = &PAR[APOS + 3 * i], *ar = &PAR[AROT + 9 * i];
        const double *b0 = &PAR[JPOS + 3 * NJ * i], *r0 = &PAR[JROT + 9 * NJ * i];
        const double arm = PAR[JPOS + 3 * (NJ * i + 1)];
        const double fore = PAR[JPOS + 3 * (NJ * i + 2)];
        double ce[3], re[3][3], m[3][3], e0, e1, e2, d0, d1, d2, off, rho;
        for (r = 0; r < 3; ++r) {
            ce[r] = p[r] + rm[r][0] * ap[0] + rm[r][1] * ap[1] + rm[r][2] * ap[2];
            for (c = 0; c < 3; ++c) {
                re[r][c] = rm[r][0] * ar[c] + rm[r][1] * ar[3 + c] + rm[r][2] * ar[6 + c];
            }
        }
        e0 = ce[0] - b0[0];
        e1 = ce[1] - b0[1];
        e2 = ce[2] - b0[2];
        d0 = r0[0] * e0 + r0[3] * e1 + r0[6] * e2;
        d1 = r0[1] * e0 + r0[4] * e1 + r0[7] * e2;
        d2 = r0[2] * e0 + r0[5] * e1 + r0[8] * e2;
        for (c = 0; c < PRP3_DOF; ++c) {
            Q(q, i, c) = 0.0;
        }
#if PRP3_PATTERN == 2 /* RUU */
        {
            const double kk = (d0 * d0 + d1 * d1 + d2 * d2 + arm * arm - fore * fore) / (2.0 * arm);
            double u[3];
            rho = hypot(d0, d1);
            if (!(fabs(kk) <= rho)) {
                return PRP3_UNREACHABLE;
            }
            Q(q, i, 0) = atan2(d1, d0) - acos(kk / rho);
            chain(i, q, f);
            for (r = 0; r < 3; ++r) {
                u[r] = (ce[0] - f->jo[i][1][0]) * f->jr[i][1][0][r]
                       + (ce[1] - f->jo[i][1][1]) * f->jr[i][1][1][r]
                       + (ce[2] - f->jo[i][1][2]) * f->jr[i][1][2][r];
            }
            angles(u[0], u[1], u[2], &Q(q, i, 1), &Q(q, i, 2));
            chain(i, q, f);
            relative(f, i, re, m);
            angles(m[0][0], m[1][0], m[2][0], &Q(q, i, 3), &Q(q, i, 4));
            off = PAR[SCALE] * m[2][1];
        }
#else /* UPS (0) or RPS (1) */
        {
#if PRP3_PATTERN == 0
            const int slide = 2;
            rho = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
            if (!(rho > 0.0)) {
                return PRP3_UNREACHABLE;
            }
            Q(q, i, 0) = atan2(d1, d0);
            Q(q, i, 1) = atan2(-d2, hypot(d0, d1));
            off = 0.0;
#else
            const int slide = 1;
            rho = hypot(d0, d1);
            if (!(rho > 0.0)) {
                return PRP3_UNREACHABLE;
            }
            Q(q, i, 0) = atan2(d1, d0);
            off = d2;
#endif
            Q(q, i, slide) = rho - arm - fore;
            chain(i, q, f);
            relative(f, i, re, m);
            rot_log(m, &Q(q, i, slide + 1));
        }
#endif
#if PRP3_PATTERN == 2
        chain(i, q, f); /* the second U's cross axis (the S joint's frames need no q_S) */
#endif
        status = limits(i, q, status);
        if (fabs(off) > PAR[PLANE]) {
            return PRP3_NOT_A_POSE;
        }
    }
    return status;
}

/* I u = R (I_body (R^T u)) with the body's inertia at PAR[at] */
static void apply_inertia(int at, double rot[3][3], const double u[3], double out[3])
{
    const double *in = &PAR[at];
    double l[3], b[3];
    int r;
    for (r = 0; r < 3; ++r) {
        l[r] = rot[0][r] * u[0] + rot[1][r] * u[1] + rot[2][r] * u[2];
    }
    for (r = 0; r < 3; ++r) {
        b[r] = in[3 * r] * l[0] + in[3 * r + 1] * l[1] + in[3 * r + 2] * l[2];
    }
    for (r = 0; r < 3; ++r) {
        out[r] = rot[r][0] * b[0] + rot[r][1] * b[1] + rot[r][2] * b[2];
    }
}

/* (m (a_G - g), I alpha + omega x I omega) of a body whose origin accelerates by acc, its
   mass centre rc from the origin (world) */
static void inertial(int at, double mass, double rot[3][3], const double om[3],
                     const double alpha[3], const double acc[3], const double rc[3],
                     double force[3], double moment[3])
{
    double k[3], h[3], s[3], iw[3], ia[3], c[3];
    int r;
    cross3(om, rc, k);
    cross3(om, k, h);
    cross3(alpha, rc, s);
    for (r = 0; r < 3; ++r) {
        force[r] = mass * (acc[r] + s[r] + h[r] - PAR[GRAV + r]);
    }
    apply_inertia(at, rot, om, iw);
    apply_inertia(at, rot, alpha, ia);
    cross3(om, iw, c);
    for (r = 0; r < 3; ++r) {
        moment[r] = ia[r] + c[r];
    }
}

/* |w t| <= 1e-8 6 max|w| max(|t|, |ref|), the twists in units of the robot's length */
static int compatible(const double nw[6], const double target[6], const double reference[6])
{
    const double scale = PAR[SCALE];
    double off = 0.0, wmax = 0.0, tmax = 0.0, size;
    int r;
    for (r = 0; r < 6; ++r) {
        const double wt = r < 3 ? nw[r] : nw[r] * scale;
        const double tt = r < 3 ? target[r] : target[r] / scale;
        const double rr = r < 3 ? reference[r] : reference[r] / scale;
        off += wt * tt;
        wmax = fmax(wmax, fabs(wt));
        tmax = fmax(tmax, fmax(fabs(tt), fabs(rr)));
    }
    size = 6.0 * wmax * tmax;
    return fabs(off) <= PRP3_COMPATIBILITY * fmax(size, 2.2250738585072014e-308);
}

/* a leg closed by an S joint: J = [[A, 1], [B, 0]] (the S's columns are the identity in
   omega and zero in v), det J = -det B; keeps A in fac[0..2][0..2], B^-1 (adjugate over
   determinant) in fac[3..5][0..2] and returns det J */
static double s_closed(double jac[6][6], double fac[6][6])
{
    double det, inv;
    int r, c;
    for (r = 0; r < 3; ++r) {
        for (c = 0; c < 3; ++c) {
            fac[r][c] = jac[r][c];
        }
    }
    fac[3][0] = jac[4][1] * jac[5][2] - jac[4][2] * jac[5][1];
    fac[4][0] = jac[4][2] * jac[5][0] - jac[4][0] * jac[5][2];
    fac[5][0] = jac[4][0] * jac[5][1] - jac[4][1] * jac[5][0];
    det = jac[3][0] * fac[3][0] + jac[3][1] * fac[4][0] + jac[3][2] * fac[5][0];
    inv = 1.0 / det;
    fac[3][0] *= inv;
    fac[4][0] *= inv;
    fac[5][0] *= inv;
    fac[3][1] = (jac[3][2] * jac[5][1] - jac[3][1] * jac[5][2]) * inv;
    fac[4][1] = (jac[3][0] * jac[5][2] - jac[3][2] * jac[5][0]) * inv;
    fac[5][1] = (jac[3][1] * jac[5][0] - jac[3][0] * jac[5][1]) * inv;
    fac[3][2] = (jac[3][1] * jac[4][2] - jac[3][2] * jac[4][1]) * inv;
    fac[4][2] = (jac[3][2] * jac[4][0] - jac[3][0] * jac[4][2]) * inv;
    fac[5][2] = (jac[3][0] * jac[4][1] - jac[3][1] * jac[4][0]) * inv;
    return -det;
}

/* a leg of 5 coordinates closed by an S joint (3-RPS): J = [[A, 1], [B, 0]], A and B of
   3 x 2; the generalised cross product of the scaled columns is (0, -b0 x b1) (scaled), so
   w_i = (0, -b0~ x b1~ / l) and mu_leg = |b0~ x b1~|; keeps A in fac[0..2][0..1] and
   B (B^T B)^-1 in fac[3..5][0..1] (det B^T B = |b0 x b1|^2); returns mu_leg */
static double s_closed5(double jac[6][6], const int kinds[6], double fac[6][6], double nw[6])
{
    const double scale = PAR[SCALE];
    const double f = (kinds[0] == 1 ? 1.0 : 1.0 / scale) * (kinds[1] == 1 ? 1.0 : 1.0 / scale);
    double b0[3], b1[3], cr[3], g00 = 0.0, g01 = 0.0, g11 = 0.0, inv;
    int r;
    for (r = 0; r < 3; ++r) {
        b0[r] = jac[3 + r][0];
        b1[r] = jac[3 + r][1];
        g00 += b0[r] * b0[r];
        g01 += b0[r] * b1[r];
        g11 += b1[r] * b1[r];
    }
    cross3(b0, b1, cr);
    inv = 1.0 / (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    for (r = 0; r < 3; ++r) {
        nw[r] = 0.0;
        nw[3 + r] = -cr[r] * f / scale;
        fac[3 + r][0] = (b0[r] * g11 - b1[r] * g01) * inv;
        fac[3 + r][1] = (b1[r] * g00 - b0[r] * g01) * inv;
        fac[r][0] = jac[r][0];
        fac[r][1] = jac[r][1];
    }
    return sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]) * fabs(f);
}

/* J^-1 t (6 coordinates) or (J^T J)^-1 J^T t (5) with the leg's factors */
static void solve_rates(double fac[6][6], double jac[6][6], const int piv[6], const double t[6],
                        double out[6])
{
    int r, c;
    if (PRP3_S_CLOSED && PRP3_DOF == 5) { /* (B^T B)^-1 B^T t_v, then t_omega - A (...) */
        for (c = 0; c < 2; ++c) {
            out[c] = fac[3][c] * t[3] + fac[4][c] * t[4] + fac[5][c] * t[5];
        }
        for (r = 0; r < 3; ++r) {
            out[2 + r] = t[r] - (fac[r][0] * out[0] + fac[r][1] * out[1]);
        }
        return;
    }
    if (PRP3_S_CLOSED) { /* B^-1 t_v, then t_omega - A (...) */
        for (r = 0; r < 3; ++r) {
            out[r] = fac[3 + r][0] * t[3] + fac[3 + r][1] * t[4] + fac[3 + r][2] * t[5];
        }
        for (r = 0; r < 3; ++r) {
            out[3 + r] = t[r] - (fac[r][0] * out[0] + fac[r][1] * out[1] + fac[r][2] * out[2]);
        }
        return;
    }
    if (PRP3_DOF == 6) {
        for (r = 0; r < 6; ++r) {
            out[r] = t[r];
        }
    } else {
        for (c = 0; c < PRP3_DOF; ++c) {
            double s = 0.0;
            for (r = 0; r < 6; ++r) {
                s += jac[r][c] * t[r];
            }
            out[c] = s;
        }
    }
    lu_solve(fac, PRP3_DOF, piv, out);
}

/* J^-T y (6 coordinates) or J (J^T J)^-1 y (5), as (M, F) */
static void transpose_solve(double fac[6][6], double jac[6][6], const int piv[6],
                            const double y[6], double out[6])
{
    double work[6];
    int r, c;
    if (PRP3_S_CLOSED && PRP3_DOF == 5) { /* M = y_S, F = B (B^T B)^-1 (y_a - A^T y_S) */
        for (c = 0; c < 2; ++c) {
            work[c] = y[c] - (fac[0][c] * y[2] + fac[1][c] * y[3] + fac[2][c] * y[4]);
        }
        for (r = 0; r < 3; ++r) {
            out[r] = y[2 + r];
            out[3 + r] = fac[3 + r][0] * work[0] + fac[3 + r][1] * work[1];
        }
        return;
    }
    if (PRP3_S_CLOSED) { /* M = y_S, F = B^-T (y_a - A^T y_S) */
        for (c = 0; c < 3; ++c) {
            work[c] = y[c] - (fac[0][c] * y[3] + fac[1][c] * y[4] + fac[2][c] * y[5]);
        }
        for (r = 0; r < 3; ++r) {
            out[r] = y[3 + r];
            out[3 + r] = fac[3][r] * work[0] + fac[4][r] * work[1] + fac[5][r] * work[2];
        }
        return;
    }
    for (c = 0; c < PRP3_DOF; ++c) {
        work[c] = y[c];
    }
    if (PRP3_DOF == 6) {
        lu_solve_transposed(fac, 6, piv, work);
        for (r = 0; r < 6; ++r) {
            out[r] = work[r];
        }
    } else {
        lu_solve(fac, PRP3_DOF, piv, work);
        for (r = 0; r < 6; ++r) {
            double s = 0.0;
            for (c = 0; c < PRP3_DOF; ++c) {
                s += jac[r][c] * work[c];
            }
            out[r] = s;
        }
    }
}

/* each body's omega, alpha and its origin's acceleration along leg i */
static void chain_motion(int i, const Frames *f, const double dq[], const double ddq[],
                         double ow[NJ][3], double oa[NJ][3], double oacc[NJ][3])
{
    double w[3] = {0.0, 0.0, 0.0}, a[3] = {0.0, 0.0, 0.0}, o[3] = {0.0, 0.0, 0.0};
    double v[3] = {0.0, 0.0, 0.0}, cc[3] = {0.0, 0.0, 0.0};
    int col = 0, k, n, r;
    for (k = 0; k < NJ; ++k) {
        const int kind = KIND[k];
        double x[3], t[3], s[3], u[3], vj[3], aj[3], vf[3], af[3];
        for (r = 0; r < 3; ++r) {
            x[r] = f->jo[i][k][r] - o[r];
        }
        cross3(w, x, t);
        cross3(a, x, s);
        cross3(w, t, u);
        for (r = 0; r < 3; ++r) {
            vj[r] = v[r] + t[r];
            aj[r] = cc[r] + s[r] + u[r];
            vf[r] = vj[r];
            af[r] = aj[r];
        }
        for (n = 0; n < KDOF[kind]; ++n) {
            const double *e = f->axes[i][col];
            const double rate = Q(dq, i, col), acc = Q(ddq, i, col);
            double h[3];
            if (kind == 1) { /* P: the frame origin on the proximal body, then the slide */
                double y[3];
                for (r = 0; r < 3; ++r) {
                    y[r] = f->fo[i][k][r] - f->jo[i][k][r];
                }
                cross3(w, y, t);
                cross3(a, y, s);
                cross3(w, t, u);
                cross3(w, e, h);
                for (r = 0; r < 3; ++r) {
                    vf[r] = vj[r] + t[r] + e[r] * rate;
                    af[r] = aj[r] + s[r] + u[r] + e[r] * acc + 2.0 * h[r] * rate;
                }
            } else if (kind == 3) { /* S: world axes */
                for (r = 0; r < 3; ++r) {
                    a[r] = a[r] + e[r] * acc;
                    w[r] = w[r] + e[r] * rate;
                }
            } else { /* R, U: an axis fixed in the proximal body */
                cross3(w, e, h);
                for (r = 0; r < 3; ++r) {
                    a[r] = a[r] + e[r] * acc + h[r] * rate;
                    w[r] = w[r] + e[r] * rate;
                }
            }
            col += 1;
        }
        for (r = 0; r < 3; ++r) {
            o[r] = f->fo[i][k][r];
            v[r] = vf[r];
            cc[r] = af[r];
            ow[k][r] = w[r];
            oa[k][r] = a[r];
            oacc[k][r] = cc[r];
        }
    }
}

/* what the legs give the platform's balance */
typedef struct {
    double jacs[PRP3_LEGS][6][6];   /* the leg Jacobians J_i (rows omega, v) */
    double normal[PRP3_LEGS][6][6]; /* the factors of J_i (6 coordinates) or J_i^T J_i (5) */
    int pivs[PRP3_LEGS][6];
    double xw[PRP3_LEGS][6];        /* x_i = J_i^-T e_a as (M, F) */
    double nw[PRP3_LEGS][6];        /* the constraint wrench w_i (legs of 5 coordinates) */
    double zl[PRP3_LEGS][6];        /* z_i = J_i^-T y0_i */
    double kmat[6][6];              /* the rows x_i, then w_i, about the platform's origin */
    double kt[6][6];                /* the factors of K^T */
    int kpiv[6];
    double ends[PRP3_LEGS][3];      /* the legs' ends c_i */
    double bw[PRP3_LEGS][NJ][3], ba[PRP3_LEGS][NJ][3], bo[PRP3_LEGS][NJ][3];
    int kinds[6], owner[6];         /* per coordinate: 0 rotation, 1 slide, 2 S; its joint */
} Legs;

static void leg_jacobian(int i, const Frames *f, Legs *s)
{
    const double *e = f->fo[i][NJ - 1];
    int c, r;
    for (r = 0; r < 3; ++r) {
        s->ends[i][r] = e[r];
    }
    for (c = 0; c < PRP3_DOF; ++c) {
        const double *ax = f->axes[i][c];
        if (s->kinds[c] == 1) {
            for (r = 0; r < 3; ++r) {
                s->jacs[i][r][c] = 0.0;
                s->jacs[i][3 + r][c] = ax[r];
            }
        } else {
            const int o = s->owner[c];
            double lever[3], m[3];
            for (r = 0; r < 3; ++r) {
                lever[r] = e[r] - f->fo[i][o][r];
                s->jacs[i][r][c] = ax[r];
            }
            cross3(ax, lever, m);
            for (r = 0; r < 3; ++r) {
                s->jacs[i][3 + r][c] = m[r];
            }
        }
    }
}

/* mu_leg of a leg of 5 coordinates: the norm of the scaled Jacobian's generalised cross
   product, which is the constraint wrench w_i (6 coordinates: jacobians) */
static double leg_measure(int i, Legs *s)
{
    const double scale = PAR[SCALE];
    double fac[6][6], big[6][6];
    int piv[6], r, c, j;
    for (r = 0; r < 6; ++r) {
        for (c = 0; c < PRP3_DOF; ++c) {
            double value = s->jacs[i][r][c];
            if (r >= 3) {
                value /= scale;
            }
            if (s->kinds[c] == 1) {
                value *= scale;
            }
            fac[r][c] = value;
        }
    }
    {
        double total = 0.0;
        for (j = 0; j < 6; ++j) {
            int rr = 0;
            double minor, value;
            for (r = 0; r < 6; ++r) {
                if (r == j) {
                    continue;
                }
                for (c = 0; c < 5; ++c) {
                    big[rr][c] = fac[r][c];
                }
                rr += 1;
            }
            minor = lu(big, 5, piv);
            value = j % 2 == 0 ? minor : -minor;
            s->nw[i][j] = j < 3 ? value : value / scale;
            total += value * value;
        }
        return sqrt(total);
    }
}

static void wrench_row(const double r[3], const double x[6], double row[6])
{
    row[0] = x[0] + r[1] * x[5] - r[2] * x[4];
    row[1] = x[1] + r[2] * x[3] - r[0] * x[5];
    row[2] = x[2] + r[0] * x[4] - r[1] * x[3];
    row[3] = x[3];
    row[4] = x[4];
    row[5] = x[5];
}

/* the Jacobians, x_i, w_i, the measures; PRP3_SINGULAR below the threshold */
static int jacobians(const double p[3], const Frames *f, Legs *s, double measures[])
{
    const double scale = PAR[SCALE];
    double det = 0.0, factor = scale * scale * scale;
    int i, r, c, k, col = 0;
    for (k = 0; k < NJ; ++k) {
        for (c = 0; c < KDOF[KIND[k]]; ++c) {
            s->kinds[col] = KIND[k] == 1 ? 1 : (KIND[k] == 3 ? 2 : 0);
            s->owner[col] = k;
            col += 1;
        }
    }
    for (r = 0; r < 6; ++r) {
        for (c = 0; c < 6; ++c) {
            s->kmat[r][c] = 0.0;
        }
    }
    for (i = 0; i < PRP3_LEGS; ++i) {
        double rr[3], e[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        for (r = 0; r < 6; ++r) {
            s->nw[i][r] = 0.0;
        }
        leg_jacobian(i, f, s);
        if (PRP3_DOF == 5) {
            measures[i] = PRP3_S_CLOSED ? s_closed5(s->jacs[i], s->kinds, s->normal[i], s->nw[i])
                                        : leg_measure(i, s);
        }
        for (r = 0; r < PRP3_DOF && !PRP3_S_CLOSED; ++r) {
            for (c = 0; c < PRP3_DOF; ++c) {
                if (PRP3_DOF == 6) {
                    s->normal[i][r][c] = s->jacs[i][r][c];
                } else {
                    double sum = 0.0;
                    for (k = 0; k < 6; ++k) {
                        sum += s->jacs[i][k][r] * s->jacs[i][k][c];
                    }
                    s->normal[i][r][c] = sum;
                }
            }
        }
        if (!PRP3_S_CLOSED) {
            det = lu(s->normal[i], PRP3_DOF, s->pivs[i]);
        } else if (PRP3_DOF == 6) {
            det = s_closed(s->jacs[i], s->normal[i]);
        }
        if (PRP3_DOF == 6) { /* the scaled Jacobian's determinant: rows of v / l, slides * l */
            double factor = 1.0 / (scale * scale * scale);
            for (c = 0; c < 6; ++c) {
                factor *= s->kinds[c] == 1 ? scale : 1.0;
            }
            measures[i] = det * factor;
        }
        e[PRP3_ACTUATED] = 1.0;
        transpose_solve(s->normal[i], s->jacs[i], s->pivs[i], e, s->xw[i]);
        for (r = 0; r < 3; ++r) {
            rr[r] = s->ends[i][r] - p[r];
        }
        wrench_row(rr, s->xw[i], s->kmat[i]);
        if (PRP3_DOF == 5) {
            wrench_row(rr, s->nw[i], s->kmat[(PRP3_LEGS + i) % 6]);
        }
    }
    /* K^T factored once: the platform's balance, and the parallel measure in units of the
       robot's length (the moment columns * l, the rows of a slide's effort / l) */
    for (r = 0; r < 6; ++r) {
        for (c = 0; c < 6; ++c) {
            s->kt[r][c] = s->kmat[c][r];
        }
    }
    for (i = 0; i < PRP3_LEGS; ++i) {
        factor /= s->kinds[PRP3_ACTUATED] == 1 ? scale : 1.0;
    }
    measures[PRP3_LEGS] = lu(s->kt, 6, s->kpiv) * factor;
    for (i = 0; i < PRP3_LEGS; ++i) {
        if (!(measures[i] * PAR[LEGSIGN + i] >= PRP3_SINGULARITY_THRESHOLD)) {
            return PRP3_SINGULAR;
        }
    }
    if (!(measures[PRP3_LEGS] * PAR[PARSIGN] >= PRP3_SINGULARITY_THRESHOLD)) {
        return PRP3_SINGULAR;
    }
    return PRP3_OK;
}

/* the q'' terms of leg i's bodies 0 .. NJ-2 onto the bias (chain_motion with q'' = 0): the
   acceleration is linear in q''; coordinate c of joint o <= k adds e_c q''_c to alpha_k and
   e_c x (o_k - o_o) q''_c to body k's origin (a rotation), or e_c q''_c to the latter (a slide) */
static void add_accelerations(int i, const Frames *f, Legs *s, const double ddq[])
{
    int k, c, r;
    for (k = 0; k < NJ - 1; ++k) {
        const double *x = f->fo[i][k];
        for (c = 0; c < PRP3_DOF && s->owner[c] <= k; ++c) {
            const int o = s->owner[c];
            const double *ax = f->axes[i][c];
            double e[3], h[3], lever[3];
            for (r = 0; r < 3; ++r) {
                e[r] = ax[r] * ddq[c];
            }
            if (s->kinds[c] == 1) {
                for (r = 0; r < 3; ++r) {
                    s->bo[i][k][r] += e[r];
                }
            } else {
                for (r = 0; r < 3; ++r) {
                    s->ba[i][k][r] += e[r];
                }
                if (o < k) {
                    for (r = 0; r < 3; ++r) {
                        lever[r] = x[r] - f->fo[i][o][r];
                    }
                    cross3(e, lever, h);
                    for (r = 0; r < 3; ++r) {
                        s->bo[i][k][r] += h[r];
                    }
                }
            }
        }
    }
}

/* dq, ddq from J_i dq = (omega, v + omega x r_i) and the chain's recursion */
static int rates(const double p[3], const double w[3], const double v[3], const double al[3],
                 const double a[3], const Frames *f, Legs *s, double dq[], double ddq[])
{
    int i, r, c;
    for (i = 0; i < PRP3_LEGS; ++i) {
        double rr[3], cw[3], d[3], g[3], st[6], ref[6], b[6];
        for (r = 0; r < 3; ++r) {
            rr[r] = s->ends[i][r] - p[r];
        }
        cross3(w, rr, cw);
        for (r = 0; r < 3; ++r) {
            st[r] = w[r];
            st[3 + r] = v[r] + cw[r];
        }
        if (PRP3_DOF == 5 && !compatible(s->nw[i], st, st)) {
            return PRP3_INCOMPATIBLE;
        }
        solve_rates(s->normal[i], s->jacs[i], s->pivs[i], st, b);
        for (c = 0; c < PRP3_DOF; ++c) {
            Q(dq, i, c) = b[c];
            Q(ddq, i, c) = 0.0;
        }
        chain_motion(i, f, dq, ddq, s->bw[i], s->ba[i], s->bo[i]); /* the bias, q'' = 0 */
        cross3(w, cw, d);
        cross3(al, rr, g);
        for (r = 0; r < 3; ++r) {
            ref[r] = s->ba[i][NJ - 1][r];
            ref[3 + r] = s->bo[i][NJ - 1][r];
        }
        for (r = 0; r < 3; ++r) {
            st[r] = al[r] - ref[r];
            st[3 + r] = a[r] + g[r] + d[r] - ref[3 + r];
        }
        if (PRP3_DOF == 5 && !compatible(s->nw[i], st, ref)) {
            return PRP3_INCOMPATIBLE;
        }
        solve_rates(s->normal[i], s->jacs[i], s->pivs[i], st, b);
        for (c = 0; c < PRP3_DOF; ++c) {
            Q(ddq, i, c) = b[c];
        }
        if (PRP3_ONE_PASS) { /* the q'' terms onto the bias */
            add_accelerations(i, f, s, b);
        } else { /* the chain again with q'' (the reference) */
            chain_motion(i, f, dq, ddq, s->bw[i], s->ba[i], s->bo[i]);
        }
    }
    return PRP3_OK;
}

/* the particular wrenches of leg i (W_n = 0, its bodies' balances from the platform inwards)
   into force, moment; z_i; the leg's share of the platform balance added to rhs */
static void leg_wrenches(int i, const double p[3], const Frames *f, Legs *s, double force[],
                         double moment[], double rhs[6])
{
    double fk[NJ][3], mk[NJ][3], y0[6], rr[3], c3[3];
    int k, r, c;
    for (r = 0; r < 3; ++r) {
        fk[NJ - 1][r] = 0.0;
        mk[NJ - 1][r] = 0.0;
    }
    for (k = NJ - 2; k >= 0; --k) {
        const double *cen = &PAR[BCEN + 3 * (2 * i + k)];
        double rot[3][3], rc[3], gk[3], fb[3], mb[3], u[3], t[3], x[3];
        for (r = 0; r < 3; ++r) {
            for (c = 0; c < 3; ++c) {
                rot[r][c] = f->fr[i][k][r][c];
            }
        }
        for (r = 0; r < 3; ++r) {
            rc[r] = rot[r][0] * cen[0] + rot[r][1] * cen[1] + rot[r][2] * cen[2];
            gk[r] = f->fo[i][k][r] + rc[r];
        }
        inertial(BINE + 9 * (2 * i + k), PAR[BMASS + 2 * i + k], rot, s->bw[i][k], s->ba[i][k],
                 s->bo[i][k], rc, fb, mb);
        for (r = 0; r < 3; ++r) {
            fk[k][r] = fk[k + 1][r] + fb[r];
            x[r] = f->fo[i][k + 1][r] - gk[r];
        }
        cross3(x, fk[k + 1], u);
        for (r = 0; r < 3; ++r) {
            x[r] = f->fo[i][k][r] - gk[r];
        }
        cross3(x, fk[k], t);
        for (r = 0; r < 3; ++r) {
            mk[k][r] = mk[k + 1][r] + u[r] - t[r] + mb[r];
        }
    }
    for (c = 0; c < PRP3_DOF; ++c) {
        const double *part = s->kinds[c] == 1 ? fk[s->owner[c]] : mk[s->owner[c]];
        y0[c] = f->axes[i][c][0] * part[0] + f->axes[i][c][1] * part[1]
                + f->axes[i][c][2] * part[2];
    }
    transpose_solve(s->normal[i], s->jacs[i], s->pivs[i], y0, s->zl[i]);
    for (r = 0; r < 3; ++r) {
        rr[r] = s->ends[i][r] - p[r];
    }
    cross3(rr, &s->zl[i][3], c3);
    for (r = 0; r < 3; ++r) {
        rhs[r] += s->zl[i][r] + c3[r];
        rhs[3 + r] += s->zl[i][3 + r];
    }
    for (k = 0; k < NJ; ++k) {
        for (r = 0; r < 3; ++r) {
            force[3 * (NJ * i + k) + r] = fk[k][r];
            moment[3 * (NJ * i + k) + r] = mk[k][r];
        }
    }
}

/* the platform's balance for (tau, lambda), then every joint's wrench */
static void wrenches(const double p[3], double rm[3][3], const double w[3], const double al[3],
                     const double a[3], const Frames *f, Legs *s, double tau[], double force[],
                     double moment[])
{
    double rhs[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, rp[3], fp[3], mp[3], c3[3];
    int i, k, r;
    for (i = 0; i < PRP3_LEGS; ++i) {
        leg_wrenches(i, p, f, s, force, moment, rhs);
    }
    for (r = 0; r < 3; ++r) {
        rp[r] = rm[r][0] * PAR[PCEN] + rm[r][1] * PAR[PCEN + 1] + rm[r][2] * PAR[PCEN + 2];
    }
    inertial(PINE, PAR[PMASS], rm, w, al, a, rp, fp, mp);
    cross3(rp, fp, c3);
    for (r = 0; r < 3; ++r) {
        rhs[r] += mp[r] + c3[r];
        rhs[3 + r] += fp[r];
    }
    lu_solve(s->kt, 6, s->kpiv, rhs);
    for (i = 0; i < PRP3_LEGS; ++i) {
        const double t = rhs[i];
        const double lam = PRP3_DOF == 5 ? rhs[(PRP3_LEGS + i) % 6] : 0.0;
        double wn[6];
        tau[i] = t;
        for (r = 0; r < 6; ++r) {
            wn[r] = t * s->xw[i][r] - s->zl[i][r] + lam * s->nw[i][r];
        }
        for (k = 0; k < NJ; ++k) {
            double l[3];
            for (r = 0; r < 3; ++r) {
                l[r] = s->ends[i][r] - f->fo[i][k][r];
            }
            cross3(l, &wn[3], c3);
            for (r = 0; r < 3; ++r) {
                force[3 * (NJ * i + k) + r] += wn[3 + r];
                moment[3 * (NJ * i + k) + r] += wn[r] + c3[r];
            }
        }
    }
}

static int prp3_refuse(double q[], double dq[], double ddq[], double tau[], double force[],
                       double moment[], int code)
{
    int n;
    for (n = 0; n < PRP3_LEGS * PRP3_DOF; ++n) {
        q[n] = NAN;
        dq[n] = NAN;
        ddq[n] = NAN;
    }
    for (n = 0; n < PRP3_LEGS; ++n) {
        tau[n] = NAN;
    }
    for (n = 0; n < PRP3_LEGS * PRP3_JOINTS * 3; ++n) {
        force[n] = NAN;
        moment[n] = NAN;
    }
    return code;
}

static int prp3_finite(const double values[], int count)
{
    int n;
    for (n = 0; n < count; ++n) {
        if (!isfinite(values[n])) {
            return 0;
        }
    }
    return 1;
}

/* the rotation's columns orthonormal and its determinant 1, to PRP3_ORTHONORMAL */
static int is_rotation(double rm[3][3])
{
    double err = 0.0, det;
    int r, c;
    for (r = 0; r < 3; ++r) {
        for (c = 0; c < 3; ++c) {
            const double s = rm[0][r] * rm[0][c] + rm[1][r] * rm[1][c] + rm[2][r] * rm[2][c];
            err = fmax(err, fabs(s - (r == c ? 1.0 : 0.0)));
        }
    }
    det = rm[0][0] * (rm[1][1] * rm[2][2] - rm[1][2] * rm[2][1])
          - rm[0][1] * (rm[1][0] * rm[2][2] - rm[1][2] * rm[2][0])
          + rm[0][2] * (rm[1][0] * rm[2][1] - rm[1][1] * rm[2][0]);
    return !(err > PRP3_ORTHONORMAL || fabs(det - 1.0) > PRP3_ORTHONORMAL);
}

static int solve(const double p[3], double rm[3][3], const double w[3], const double v[3],
                 const double al[3], const double a[3], double q[], double dq[], double ddq[],
                 double tau[], double force[], double moment[])
{
    Frames f;
    Legs s;
    double measures[PRP3_LEGS + 1];
    int status;
    if (!is_rotation(rm)) {
        return PRP3_NOT_ROTATION;
    }
    status = geometry(p, rm, q, &f);
    if (status != PRP3_OK) {
        return status;
    }
    status = jacobians(p, &f, &s, measures);
    if (status != PRP3_OK) {
        return status;
    }
    status = rates(p, w, v, al, a, &f, &s, dq, ddq);
    if (status != PRP3_OK) {
        return status;
    }
    wrenches(p, rm, w, al, a, &f, &s, tau, force, moment);
    return PRP3_OK;
}

int prp3_inverse_dynamics(const double position[3], const double rotation[9],
                          const double omega[3], const double velocity[3],
                          const double alpha[3], const double acceleration[3],
                          double q[PRP3_LEGS * PRP3_DOF], double dq[PRP3_LEGS * PRP3_DOF],
                          double ddq[PRP3_LEGS * PRP3_DOF], double tau[PRP3_LEGS],
                          double force[PRP3_LEGS * PRP3_JOINTS * 3],
                          double moment[PRP3_LEGS * PRP3_JOINTS * 3])
{
    double rm[3][3];
    int r, c, status;
    for (r = 0; r < 3; ++r) {
        if (!(isfinite(position[r]) && isfinite(omega[r]) && isfinite(velocity[r])
              && isfinite(alpha[r]) && isfinite(acceleration[r]))) {
            return prp3_refuse(q, dq, ddq, tau, force, moment, PRP3_NOT_FINITE);
        }
        for (c = 0; c < 3; ++c) {
            if (!isfinite(rotation[3 * r + c])) {
                return prp3_refuse(q, dq, ddq, tau, force, moment, PRP3_NOT_FINITE);
            }
            rm[r][c] = rotation[3 * r + c];
        }
    }
    status = solve(position, rm, omega, velocity, alpha, acceleration, q, dq, ddq, tau, force,
                   moment);
    if (status != PRP3_OK) {
        return prp3_refuse(q, dq, ddq, tau, force, moment, status);
    }
    /* the inputs are finite: an output that is not has overflowed */
    if (!(prp3_finite(q, PRP3_LEGS * PRP3_DOF) && prp3_finite(dq, PRP3_LEGS * PRP3_DOF)
          && prp3_finite(ddq, PRP3_LEGS * PRP3_DOF) && prp3_finite(tau, PRP3_LEGS)
          && prp3_finite(force, PRP3_LEGS * PRP3_JOINTS * 3)
          && prp3_finite(moment, PRP3_LEGS * PRP3_JOINTS * 3))) {
        return prp3_refuse(q, dq, ddq, tau, force, moment, PRP3_OVERFLOW);
    }
    return PRP3_OK;
}
"""
