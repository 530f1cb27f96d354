"""A moving obstacle whose route goes through a wall or a static obstacle is a warning
naming both lines: nothing stops a moving obstacle, so it would pass through."""

from __future__ import annotations

import warnings

import pytest

from btnav.core.errors import BtnavWarning
from btnav.core.resources import bundled_dir
from btnav.sim.world_spec import WorldSpec, load_world_spec

OFFICE = bundled_dir("worlds") / "small_office.yaml"

ROOM = """\
world: room
bounds: [[0, 0], [10, 10]]
walls:
  - [[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]]
  - {points: [[5, 0], [5, 4]], thickness: 0.2}
obstacles:
  - box: {center: [2, 8], size: [1.0, 1.0]}
  - circle: {center: [8, 8], radius: 0.5}
  - polygon: {points: [[7, 2], [9, 2], [9, 3], [8, 3], [8, 4], [7, 4]]}
MOVER
robot:
  pose: [1, 1, 0]
"""


def load(mover: str) -> list[BtnavWarning]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        spec = WorldSpec.from_text(ROOM.replace("MOVER", mover), "room.yaml")
    warned = [w.message for w in caught if isinstance(w.message, BtnavWarning)]
    assert warned == spec.load_warnings  # what the CLI prints is what the spec holds
    return warned


def test_the_office_person_walks_clear_of_everything():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert load_world_spec(OFFICE).load_warnings == []


def test_a_circle_through_a_wall_names_both_lines():
    (w,) = load(
        "  - circle: {center: [3, 2], radius: 0.3,\n      moves: {path: [[7, 1]], speed: 0.5}}"
    )
    assert str(w) == (
        "room.yaml:11: obstacles[3].circle.moves: the route of this moving circle goes through "
        "walls[1] (line 5) on its way from (3, 2) to (7, 1); moving obstacles pass through "
        "whatever is in their way"
    )


@pytest.mark.parametrize(
    "mover, through",
    [
        (  # a box sliding into the circle
            "  - box: {center: [6, 8], size: [0.4, 0.4], moves: {path: [[9, 8]], speed: 1}}",
            "the circle obstacles[1] (line 8)",
        ),
        (  # a circle into the box, on the second leg of its route
            "  - circle: {center: [4, 6], radius: 0.2, moves: {path: [[4, 8], [2, 8]], speed: 1}}",
            "the box obstacles[0] (line 7)",
        ),
        (  # a triangle through the notch of the concave polygon into its foot
            "  - polygon: {points: [[8.2, 5.8], [8.8, 5.8], [8.5, 6.2]],"
            " moves: {path: [[8.5, 2.9]], speed: 1}}",
            "the polygon obstacles[2] (line 9)",
        ),
    ],
)
def test_every_kind_of_mover_and_obstacle_is_checked(mover: str, through: str):
    (w,) = load(mover)
    assert w.line == 10 and through in w.message


@pytest.mark.parametrize(
    "mover",
    [
        # beside the wall, 5 cm of air between them
        "  - circle: {center: [5.45, 1], radius: 0.3, moves: {path: [[5.45, 3]], speed: 1}}",
        # into the concave polygon's notch (x 8-9, y 3-4 is empty) and back
        "  - circle: {center: [8.5, 6], radius: 0.3, moves: {path: [[8.5, 3.6]], speed: 1}}",
        # over the end of the wall (y > 4), clear of it
        "  - box: {center: [3, 5], size: [0.4, 0.4], moves: {path: [[7, 5]], speed: 1, loop: true}}",
    ],
)
def test_a_route_that_passes_close_but_clear_is_no_warning(mover: str):
    assert load(mover) == []
