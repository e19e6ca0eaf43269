"""The robot model: defaults of docs/model.md, validation with precise messages, TOML round trip."""

from __future__ import annotations

import dataclasses
import math
import re
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from prp3 import (
    InputFileError,
    Limits,
    LinkParameters,
    ParameterError,
    PistonParameters,
    PlatformParameters,
    Prp3Error,
    Robot,
)
from prp3.model.robot import robot_template
from strategies import robots


# ------------------------------------------------------------------ defaults
def test_defaults_are_the_papers_robot() -> None:
    # docs/model.md: l0 = 0.3 m, m1 = 1, m2 = 0.75, m3 = 3 kg, I2 = 6.25e-4 kg·m², I1 = 0,
    # centres of mass at the joints, g = (0, −9.81) m/s², no limits.
    robot = Robot()
    assert robot.l0 == 0.3
    assert robot.gravity == (0.0, -9.81)
    assert (robot.piston.mass, robot.piston.inertia, robot.piston.com) == (1.0, 0.0, (0.0, 0.0))
    assert (robot.link.mass, robot.link.inertia, robot.link.com) == (0.75, 6.25e-4, (0.0, 0.0))
    assert (robot.platform.mass, robot.platform.inertia) == (3.0, None)
    assert robot.limits == Limits() and robot.limits.stroke is None
    assert robot.limits.max_force is None
    # l = l0·√3 = 0.519615 m; I3 = m3·l²/12 = 3·0.27/12 = 0.0675 kg·m²
    assert robot.edge == pytest.approx(0.3 * math.sqrt(3), rel=1e-15)
    assert robot.platform_inertia == pytest.approx(0.0675, rel=1e-14)


def test_platform_inertia_is_recomputed_unless_given() -> None:
    # l0 = 0.4, m3 = 2: l² = 3·0.16 = 0.48, I3 = 2·0.48/12 = 0.08 kg·m²
    robot = Robot(l0=0.4, platform=PlatformParameters(mass=2.0))
    assert robot.platform_inertia == pytest.approx(0.08, rel=1e-14)
    given_inertia = Robot(l0=0.4, platform=PlatformParameters(mass=2.0, inertia=0.5))
    assert given_inertia.platform_inertia == 0.5
    assert Robot(platform=PlatformParameters(inertia=0.0)).platform_inertia == 0.0


def test_numbers_are_stored_as_floats() -> None:
    robot = Robot(
        l0=np.float32(0.5),  # type: ignore[arg-type]
        gravity=(0, -10),
        piston=PistonParameters(mass=2, com=(np.int64(0), 0.01)),  # type: ignore[arg-type]
    )
    assert type(robot.l0) is float and robot.l0 == 0.5
    assert robot.gravity == (0.0, -10.0) and all(type(v) is float for v in robot.gravity)
    assert type(robot.piston.mass) is float
    assert robot.piston.com == (0.0, 0.01) and type(robot.piston.com[0]) is float


def test_robot_is_immutable() -> None:
    robot = Robot()
    with pytest.raises(dataclasses.FrozenInstanceError):
        robot.l0 = 0.5  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        robot.platform.mass = 1.0  # type: ignore[misc]
    assert Robot() == robot and hash(Robot()) == hash(robot)


# ------------------------------------------------------------------ refusals
BAD_POSITIVE = [0.0, -1.0, math.nan, math.inf, -math.inf, "0.3", True, None, [0.3]]
BAD_NON_NEGATIVE = [-1e-9, -1.0, math.nan, math.inf, "1", False, [0.1]]


@pytest.mark.parametrize("value", BAD_POSITIVE)
def test_l0_must_be_positive_and_finite(value: Any) -> None:
    with pytest.raises(ParameterError) as info:
        Robot(l0=value)
    message = str(info.value)
    assert "l0" in message and repr(value) in message and "\n" not in message


@pytest.mark.parametrize("value", BAD_POSITIVE)
@pytest.mark.parametrize(
    ("kind", "key"),
    [(PistonParameters, "piston"), (LinkParameters, "link"), (PlatformParameters, "platform")],
)
def test_masses_must_be_positive_and_finite(kind: Any, key: str, value: Any) -> None:
    with pytest.raises(ParameterError) as info:
        kind(mass=value)
    assert f"{key}.mass" in str(info.value) and repr(value) in str(info.value)
    with pytest.raises(ParameterError, match=rf"{key}\.mass"):
        Robot.from_mapping({key: {"mass": value}})


@pytest.mark.parametrize("value", BAD_NON_NEGATIVE)
@pytest.mark.parametrize(
    ("kind", "key"),
    [(PistonParameters, "piston"), (LinkParameters, "link"), (PlatformParameters, "platform")],
)
def test_inertias_must_be_non_negative_and_finite(kind: Any, key: str, value: Any) -> None:
    with pytest.raises(ParameterError) as info:
        kind(inertia=value)
    if value is None and kind is PlatformParameters:
        pytest.fail("unreachable: None means the uniform plate")  # pragma: no cover
    assert f"{key}.inertia" in str(info.value) and repr(value) in str(info.value)


@pytest.mark.parametrize("kind", [PistonParameters, LinkParameters])
def test_only_the_platform_inertia_may_be_omitted(kind: Any) -> None:
    # None means "the uniform plate" for the platform only.
    assert PlatformParameters(inertia=None).inertia is None
    with pytest.raises(ParameterError, match=r"inertia.*None"):
        kind(inertia=None)


@pytest.mark.parametrize(
    ("value", "names"),
    [
        ([0.0], "piston.com"),
        ([0.0, 0.0, 0.0], "piston.com"),
        ("ab", "piston.com"),
        (3.0, "piston.com"),
        ([math.nan, 0.0], "piston.com[0]"),
        ([0.0, math.inf], "piston.com[1]"),
        (["a", 0.0], "piston.com[0]"),
        ([True, 0.0], "piston.com[0]"),
    ],
)
def test_centre_of_mass_must_be_a_pair_of_finite_numbers(value: Any, names: str) -> None:
    with pytest.raises(ParameterError) as info:
        PistonParameters(com=value)
    assert names in str(info.value)
    with pytest.raises(ParameterError, match=names.replace("piston", "link").replace("[", r"\[")):
        Robot.from_mapping({"link": {"com": value}})


@pytest.mark.parametrize(
    ("value", "names"),
    [
        ([0.0], "gravity"),
        ([0.0, -9.81, 0.0], "gravity"),
        ("down", "gravity"),
        ([0.0, math.nan], "gravity[1]"),
        ([math.inf, 0.0], "gravity[0]"),
        ([0.0, "x"], "gravity[1]"),
        ([False, -9.81], "gravity[0]"),
    ],
)
def test_gravity_must_be_a_pair_of_finite_numbers(value: Any, names: str) -> None:
    with pytest.raises(ParameterError) as info:
        Robot(gravity=value)
    assert names in str(info.value) and "\n" not in str(info.value)
    with pytest.raises(ParameterError) as info:
        Robot.from_mapping({"gravity": value})
    assert names in str(info.value)


def test_zero_gravity_and_zero_inertias_are_valid() -> None:
    robot = Robot(
        gravity=(0.0, 0.0),
        piston=PistonParameters(inertia=0.0),
        link=LinkParameters(inertia=0.0),
        platform=PlatformParameters(inertia=0.0),
    )
    assert robot.gravity == (0.0, 0.0) and robot.platform_inertia == 0.0


@pytest.mark.parametrize(
    ("mapping", "key"),
    [
        ({"platfrom": {}}, "'platfrom'"),
        ({"L0": 0.3}, "'L0'"),
        ({"piston": {"radius": 0.1}}, "'piston.radius'"),
        ({"link": {"colour": "red"}}, "'link.colour'"),
        ({"platform": {"com": [0.0, 0.0]}}, "'platform.com'"),
        ({"limits": {"speed": 1.0}}, "'limits.speed'"),
    ],
)
def test_unknown_keys_are_refused(mapping: dict[str, Any], key: str) -> None:
    with pytest.raises(ParameterError) as info:
        Robot.from_mapping(mapping)
    assert f"unknown key {key}" in str(info.value)
    assert "expected one of" in str(info.value)


@pytest.mark.parametrize("table", ["piston", "link", "platform", "limits"])
def test_tables_must_be_tables(table: str) -> None:
    with pytest.raises(ParameterError, match=rf"\[{table}\] must be a table of keys, got 3"):
        Robot.from_mapping({table: 3})


def test_top_level_must_be_a_mapping() -> None:
    with pytest.raises(ParameterError, match=r"must be a table of keys, got \[1, 2\]"):
        Robot.from_mapping([1, 2])  # type: ignore[arg-type]


@pytest.mark.parametrize("name", ["piston", "link", "platform", "limits"])
def test_parts_must_have_their_type(name: str) -> None:
    with pytest.raises(ParameterError, match=rf"{name} must be a \w+, got 3"):
        Robot(**{name: 3})  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("stroke", "fragment"),
    [
        ((0.1, 0.2), "lower < 0 < upper"),
        ((-0.1, 0.0), "lower < 0 < upper"),
        ((0.0, 0.1), "lower < 0 < upper"),
        ((0.1, -0.1), "lower < 0 < upper"),
        ((-0.1, math.nan), "limits.stroke[1]"),
        ((-0.1,), "limits.stroke"),
        ("wide", "limits.stroke"),
    ],
)
def test_stroke_limits_are_validated(stroke: Any, fragment: str) -> None:
    with pytest.raises(ParameterError) as info:
        Limits(stroke=stroke)
    assert fragment in str(info.value)


@pytest.mark.parametrize("value", [0.0, -5.0, math.nan, math.inf, "10", True])
def test_force_limit_is_validated(value: Any) -> None:
    with pytest.raises(ParameterError) as info:
        Limits(max_force=value)
    assert "limits.max_force" in str(info.value) and repr(value) in str(info.value)


def test_valid_limits_are_kept() -> None:
    limits = Limits(stroke=[-0.2, 0.1], max_force=400)  # type: ignore[arg-type]
    assert limits.stroke == (-0.2, 0.1) and limits.max_force == 400.0


def test_partial_mapping_keeps_the_other_defaults() -> None:
    robot = Robot.from_mapping({"link": {"mass": 2.0}, "gravity": [0.0, 0.0]})
    assert robot == Robot(link=LinkParameters(mass=2.0), gravity=(0.0, 0.0))
    assert robot.link.inertia == 6.25e-4 and robot.piston == PistonParameters()
    assert Robot.from_mapping({}) == Robot()


def test_every_error_is_a_prp3_error() -> None:
    for error in (ParameterError, InputFileError):
        assert issubclass(error, Prp3Error) and issubclass(error, ValueError)


# ------------------------------------------------------------------ TOML files
def _write(tmp_path: Path, text: str, name: str = "robot.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("text", "fragments"),
    [
        ("l0 = nan\n", ["l0", "nan"]),
        ("l0 = -inf\n", ["l0", "-inf"]),
        ("l0 = 0\n", ["l0", "got 0"]),
        ('l0 = "0.3"\n', ["l0", "'0.3'"]),
        ("l0 = true\n", ["l0", "True"]),
        ("gravity = [0.0, inf]\n", ["gravity[1]", "inf"]),
        ("gravity = [0.0]\n", ["gravity", "[0.0]"]),
        ("[piston]\nmass = -1.0\n", ["piston.mass", "-1.0"]),
        ("[link]\ninertia = -1e-3\n", ["link.inertia", "-0.001"]),
        ("[platform]\ninertia = nan\n", ["platform.inertia", "nan"]),
        ("[link]\ncom = [0.0, 0.0, 0.0]\n", ["link.com", "[0.0, 0.0, 0.0]"]),
        ("[link]\ncolour = 1\n", ["'link.colour'"]),
        ("wheels = 3\n", ["'wheels'"]),
        ("piston = 3\n", ["[piston]", "3"]),
        ("[limits]\nstroke = [0.1, 0.2]\n", ["limits.stroke", "[0.1, 0.2]"]),
    ],
)
def test_bad_values_in_files_name_the_file_and_key(
    tmp_path: Path, text: str, fragments: list[str]
) -> None:
    path = _write(tmp_path, text)
    with pytest.raises(ParameterError) as info:
        Robot.from_toml(path)
    message = str(info.value)
    assert message.startswith(str(path)) and "\n" not in message
    for fragment in fragments:
        assert fragment in message, (fragment, message)


@pytest.mark.parametrize(
    ("text", "line", "column"),
    [("l0 = \n", 1, 6), ("l0 = 0.3\nl0 = 0.4\n", 2, 9), ("[piston\nmass = 1\n", 1, 8)],
)
def test_malformed_toml_names_file_line_and_column(
    tmp_path: Path, text: str, line: int, column: int
) -> None:
    path = _write(tmp_path, text)
    with pytest.raises(InputFileError) as info:
        Robot.from_toml(path)
    message = str(info.value)
    assert message.startswith(f"{path}:{line}:{column}: invalid TOML") and "\n" not in message


@pytest.mark.parametrize(
    ("text", "named"),
    [
        ("l0 = 0.3\n'l0' = 0.4\n", "the key 'l0' is set twice"),
        ('[platform]\n"mass" = 1.0\nmass = 2.0\n', "the key 'mass' of [platform] is set twice"),
        ('platform.mass = 1.0\n"platform" . "mass" = 2.0\n', "the key 'platform.mass' is set"),
        ("[limits]\nstroke = [-0.1, 0.1]\n[piston]\nmass = 1\n\tmass=2\n", "'mass' of [piston]"),
    ],
)
def test_a_key_set_twice_is_named_with_its_table(tmp_path: Path, text: str, named: str) -> None:
    # tomllib says only "Cannot overwrite a value"; the key is the one of the line it points at
    path = _write(tmp_path, text)
    with pytest.raises(InputFileError) as info:
        Robot.from_toml(path)
    message = str(info.value)
    assert message.startswith(f"{path}:") and named in message and "\n" not in message


def test_unreadable_files_are_input_file_errors(tmp_path: Path) -> None:
    missing = tmp_path / "missing.toml"
    with pytest.raises(InputFileError, match=r"missing\.toml"):
        Robot.from_toml(missing)
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"l0 = 0.3 # \xff\xfe\n")
    with pytest.raises(InputFileError, match=r"binary\.toml.*UTF-8"):
        Robot.from_toml(binary)
    with pytest.raises(InputFileError, match=re.escape(str(tmp_path))):
        Robot.from_toml(tmp_path)


def test_template_reads_back_as_the_default_robot(tmp_path: Path) -> None:
    text = robot_template()
    assert "l0 = 0.3" in text and "[piston]" in text and "#" in text
    assert Robot.from_toml(_write(tmp_path, text)) == Robot()
    # commented-out optional keys stay optional
    assert "inertia" not in tomllib.loads(text)["platform"]


def test_spec_example_file_reads_as_the_defaults(tmp_path: Path) -> None:
    # The ROBOT.toml of docs/model.md, verbatim (platform inertia given: 0.0675).
    text = """l0 = 0.3
gravity = [0.0, -9.81]
[piston]
mass = 1.0
inertia = 0.0
com = [0.0, 0.0]
[link]
mass = 0.75
inertia = 6.25e-4
com = [0.0, 0.0]
[platform]
mass = 3.0
inertia = 0.0675
"""
    robot = Robot.from_toml(_write(tmp_path, text))
    assert robot == Robot(platform=PlatformParameters(inertia=0.0675))
    assert robot.platform_inertia == pytest.approx(Robot().platform_inertia, rel=1e-14)


limits_strategy = st.builds(
    Limits,
    stroke=st.one_of(
        st.none(),
        st.tuples(st.floats(-1.0, -1e-6), st.floats(1e-6, 1.0)),
    ),
    max_force=st.one_of(st.none(), st.floats(1e-3, 1e4)),
)


@given(robot=robots(), limits=limits_strategy, comments=st.booleans())
def test_toml_round_trip(robot: Robot, limits: Limits, comments: bool) -> None:
    robot = dataclasses.replace(robot, limits=limits)
    text = robot_template(robot, comments=comments)
    assert Robot.from_mapping(tomllib.loads(text)) == robot
    assert Robot.from_mapping(tomllib.loads(robot.to_toml())) == robot


def test_toml_round_trip_through_a_file(tmp_path: Path) -> None:
    robot = Robot(
        l0=0.45,
        gravity=(1.5, -3.25),
        piston=PistonParameters(mass=1.25, inertia=0.01, com=(0.01, -0.02)),
        link=LinkParameters(mass=0.5, inertia=1e-3, com=(-0.03, 0.004)),
        platform=PlatformParameters(mass=2.5, inertia=0.123456789012345),
        limits=Limits(stroke=(-0.15, 0.25), max_force=321.5),
    )
    assert Robot.from_toml(_write(tmp_path, robot.to_toml())) == robot
    assert Robot.from_toml(_write(tmp_path, robot_template(robot), "t.toml")) == robot


@pytest.mark.parametrize(
    ("value", "fragment"),
    [
        ("heavy", "must be a number, got 'heavy' (str)"),
        (True, "must be a number, got True (bool)"),
        (math.nan, "must be a finite number, got nan"),
        (-2.0, "must be a positive finite number (kg), got -2.0"),
    ],
)
def test_mass_messages_say_what_is_wrong(value: Any, fragment: str) -> None:
    with pytest.raises(ParameterError) as info:
        Robot.from_mapping({"link": {"mass": value}})
    assert str(info.value) == f"robot: link.mass {fragment}"


def test_a_robot_file_may_start_with_a_byte_order_mark(tmp_path: Path) -> None:
    path = tmp_path / "bom.toml"
    path.write_bytes("\ufeff[platform]\nmass = 2.0\n".encode())
    assert Robot.from_toml(path).platform.mass == 2.0


# ------------------------------------------------------------ [spring.actuator]
def test_the_spring_table_reads_validates_and_round_trips(tmp_path: Path) -> None:
    from prp3.model.parameters import Spring, SpringParameters

    text = "[spring.actuator]\nstiffness = 500\nrest = -0.01\ndamping = 2.5\n"
    path = tmp_path / "robot.toml"
    path.write_text(text)
    robot = Robot.from_toml(path)
    assert robot.spring == Spring(SpringParameters(stiffness=500.0, rest=-0.01, damping=2.5))
    assert type(robot.spring.actuator.stiffness) is float
    assert Robot.from_mapping(tomllib.loads(robot.to_toml())) == robot
    assert Robot().spring is None and "spring" not in Robot().to_toml()
    assert [e.name for e in robot.elements] == ["gravity", "spring.actuator"]
    for bad, message in (
        (
            "stiffness = -1.0",
            "spring.actuator.stiffness must be a non-negative finite number (N/m)",
        ),
        ("damping = -2.0", "spring.actuator.damping must be a non-negative finite number (N·s/m)"),
        ("rest = nan", "spring.actuator.rest must be a finite number"),
        ("length = 0.1", "unknown key 'spring.actuator.length'"),
    ):
        path.write_text(f"[spring.actuator]\n{bad}\n")
        with pytest.raises(ParameterError, match=re.escape(message)) as caught:
            Robot.from_toml(path)
        assert caught.value.file == str(path) and caught.value.key.startswith("spring")
    with pytest.raises(ParameterError, match=re.escape("unknown key 'spring.platform'")):
        Robot.from_mapping({"spring": {"platform": {}}})


def test_the_template_documents_the_spring_keys() -> None:
    # the commented keys of prp3 robot --template, uncommented, are a valid spring table
    lines = robot_template().split("# [spring.actuator]", 1)[1].splitlines()[:4]
    text = "[spring.actuator]\n" + "\n".join(line.lstrip("# ").split("#")[0] for line in lines[1:])
    robot = Robot.from_mapping(tomllib.loads(text))
    assert robot.spring is not None and robot.spring.actuator.stiffness == 0.0
    assert {"stiffness", "rest", "damping"} <= set(tomllib.loads(text)["spring"]["actuator"])
    with_spring = dataclasses.replace(Robot(), spring=robot.spring)
    template = robot_template(with_spring)
    assert "[spring.actuator]" in template and "N/m" in template and "N s/m" in template
    assert Robot.from_mapping(tomllib.loads(template)) == with_spring
