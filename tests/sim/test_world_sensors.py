"""Sensors named in the world file: plugin lookup, params validated at their line, own seeds."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest
from pydantic import Field

from btnav.core.errors import PluginError, WorldError
from btnav.plugins import register, unregister
from btnav.sim.sensor import Sensor
from btnav.sim.world import World
from btnav.sim.world_sensors import make_sensors
from btnav.sim.world_spec import WorldSpec

NAME = "test/NoisyCompass"


@pytest.fixture
def compass() -> Iterator[type[Sensor]]:
    """A throwaway sensor plugin: the robot's yaw plus seeded noise."""

    @register("sensor", NAME, aliases=["test_compass"])
    class NoisyCompass(Sensor):
        class Params(Sensor.Params):
            noise_std: float = Field(0.01, ge=0)

        def measure(self, now: float) -> float:
            return self.world.robot_pose.yaw + self.rng.normal(0.0, self.params.noise_std)

    yield NoisyCompass
    unregister("sensor", NAME)


def world_with(sensors: str) -> World:
    text = f"""
bounds: [[0, 0], [5, 5]]
robot:
  pose: [1, 1, 0.5]
  sensors:
{sensors}
"""
    return World(WorldSpec.from_text(text, "sensors.yaml"))


TWO = """    - test_compass: {frame: compass_a, noise_std: 0.1}
    - test/NoisyCompass: {frame: compass_b, pose: [0.1, 0, 0], rate: 5, noise_std: 0.1}
"""


def test_each_entry_becomes_its_plugin_with_validated_params(compass):
    world = world_with(TWO)
    a, b = make_sensors(world, seed=0)
    assert isinstance(a, compass) and isinstance(b, compass)
    assert a.frame_id == "compass_a" and b.rate == 5 and b.mount.x == 0.1
    assert a.params.noise_std == 0.1
    assert abs(a.measure(0.0) - 0.5) < 1.0


def test_each_sensor_has_its_own_stream_and_one_seed_repeats(compass):
    def readings(seed: int) -> np.ndarray:
        sensors = make_sensors(world_with(TWO), seed=seed)
        return np.array([[s.measure(0.0) for s in sensors] for _ in range(5)])

    r = readings(1)
    assert not np.array_equal(r[:, 0], r[:, 1])  # two frames, two streams
    np.testing.assert_array_equal(r, readings(1))
    assert not np.array_equal(r, readings(2))


def test_unknown_sensor_plugin_is_located_with_close_names(compass):
    world = world_with("    - test_compas: {frame: c}\n")
    with pytest.raises(PluginError) as info:
        make_sensors(world)
    assert info.value.file == "sensors.yaml" and info.value.line == 6
    assert info.value.suggestion == "test_compass"


def test_bad_sensor_param_names_line_and_spelling(compass):
    world = world_with("    - test_compass:\n        frame: c\n        noise_sdt: 0.1\n")
    with pytest.raises(WorldError) as info:
        make_sensors(world)
    err = info.value
    assert err.line == 8 and err.suggestion == "noise_std"
    assert err.key == "robot.sensors[0].test_compass.noise_sdt"


def test_sensor_frames_must_be_unique_and_not_the_robots_own(compass):
    with pytest.raises(WorldError, match="two sensors use frame 'c'"):
        make_sensors(world_with("    - test_compass: {frame: c}\n    - test_compass: {frame: c}\n"))
    with pytest.raises(WorldError, match="robot's own frames"):
        make_sensors(world_with("    - test_compass: {frame: base_link}\n"))


def test_a_sensor_entry_must_be_a_one_key_mapping():
    with pytest.raises(WorldError, match="one-key mapping") as info:
        world_with("    - {lidar: {frame: a}, sonar: {frame: b}}\n")
    assert info.value.key == "robot.sensors"


def test_the_office_lidar_is_built_from_the_world_file_and_scans_the_world():
    """The built-in lidar comes without an import by the user, and sees the office's walls."""
    from btnav.core.resources import bundled_dir

    world = World.from_file(bundled_dir("worlds") / "small_office.yaml", seed=0)
    [lidar] = make_sensors(world, seed=0)
    assert lidar.plugin_name == "lidar" and lidar.frame_id == "laser"
    scan = lidar.measure(world.time)
    assert len(scan.ranges) == 360
    ahead = int(np.argmin(np.abs(scan.angles)))
    # From (1.1, 1.0) looking along +x, the x = 4 wall's face is at x = 3.95.
    assert scan.ranges[ahead] == pytest.approx(3.95 - 1.1, abs=0.06)
