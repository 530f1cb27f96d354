"""Build the robot's sensors from the world file: plugin lookup, params validation, seeding."""

from __future__ import annotations

from ..core.errors import BtnavError, WorldError
from ..core.frames import BASE_FOOTPRINT, BASE_LINK, MAP, ODOM
from ..core.rng import stream
from ..core.validation import validate
from ..core.yaml_io import YamlMap
from ..plugins import lookup
from .sensor import Sensor
from .world import World

#: Frames the REP-105 chain owns; a sensor cannot take one of these names.
RESERVED_FRAMES = (MAP, ODOM, BASE_FOOTPRINT, BASE_LINK)


def make_sensors(world: World, seed: int = 0) -> list[Sensor]:
    """One `Sensor` per `robot.sensors` entry, each on its own `stream(seed, "sensor", frame)`.

    An unknown plugin name, a bad parameter or a duplicate frame is a `BtnavError`
    located at the entry's line in the world file.
    """
    sensors: list[Sensor] = []
    frames: dict[str, int | None] = {}
    # A robot from another file (a mission's `robot:`) is located in that file.
    file = world.spec.robot_file if world.spec.robot_replaced else world.file
    for i, (name, params_doc, line) in enumerate(world.sensor_specs()):
        key = ["robot", "sensors", i, name]
        try:
            cls = lookup("sensor", name)
        except BtnavError as exc:
            raise exc.located(file=file, line=line, key=key) from None
        doc = params_doc if params_doc is not None else YamlMap(file=file, line=line)
        params = validate(cls.Params, doc, file=file, key_prefix=key, error_cls=WorldError)
        frame = params.frame
        where = dict(file=file, line=world.spec.line_of(*key, "frame") or line, key=key)
        if frame in RESERVED_FRAMES:
            raise WorldError(
                f"sensor frame '{frame}' is one of the robot's own frames "
                f"({', '.join(RESERVED_FRAMES)}); name the sensor's frame, e.g. 'laser'",
                **where,
            )
        if frame in frames:
            raise WorldError(
                f"two sensors use frame '{frame}' (the other at line {frames[frame]}); "
                "each sensor needs its own frame",
                **where,
            )
        frames[frame] = line
        sensor = cls(name, params)
        sensor.configure(world, stream(seed, "sensor", frame))
        sensors.append(sensor)
    return sensors
