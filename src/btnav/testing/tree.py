"""A tree under test: built from YAML (or XML) text or a file, ticked on sim time.

With fake servers (the default) the tree runs on a small runtime of its own: an empty
world with the robot at rest at its start pose (or a world you give), the REP-105
frames, a `FakeServer` for every action server its nodes call (see `fake_servers`) and
a `FakeStack` for the services. Nodes that need more (a costmap) can be stubbed with
`nodes={"ValidatePath": "SUCCESS"}` (a status, one per tick in a list, the last
repeating, or a callable returning one). With `navigator=` the tree calls that
navigator's real servers and each tick steps its whole runtime.

Each `tick()` is bt_navigator's loop: tick the tree once at the current sim time, then
advance sim time by one period (`bt_loop_duration`, 10 ms) while the servers work.
Every status change goes to `bt_log` (and to `bt_log.jsonl` in the run folder).
"""

from __future__ import annotations

import io
import json
from collections.abc import Callable, Iterator, Mapping, MutableMapping, Sequence
from os import PathLike
from pathlib import Path
from types import SimpleNamespace
from typing import Any, TextIO

import py_trees
from py_trees.behaviour import Behaviour
from py_trees.common import Status

from ..bt import blackboard
from ..bt.base import adopt
from ..bt.bundled import find_tree
from ..bt.loader import build_tree, load_document
from ..core.errors import UnknownNameError
from ..core.geometry import Pose2D
from ..core.suggest import best_match
from ..core.yaml_io import load_yaml_text
from ..mission.bt_log import STATUS_NAMES, BtLog
from ..nav.runtime import Runtime
from ..sim.world import World
from ..sim.world_spec import WorldSpec, load_world_spec
from .fake_servers import STATUSES, Answers, FakeServer, FakeStack, make_servers
from .records import matches, short_names

Blackboard = py_trees.blackboard.Blackboard
_STATUS = {"SUCCESS": Status.SUCCESS, "FAILURE": Status.FAILURE, "RUNNING": Status.RUNNING}

#: Nav2's default bt_loop_duration (s).
DEFAULT_PERIOD = 0.01
#: The world of a tree with fake servers when none is given: room to move, nothing to hit.
EMPTY_WORLD = """\
world: btnav_testing
bounds: [[-50, -50], [50, 50]]
robot:
  pose: [0.0, 0.0, 0.0]
"""


def _looks_like_text(source: str) -> bool:
    """YAML or XML text rather than a file name (which has no line break, `:` or `<`)."""
    return (
        "\n" in source
        or source.lstrip().startswith("<")
        or (":" in source and not Path(source).is_file())
    )


def make_world(source: str | PathLike[str] | World | None = None, seed: int = 0) -> World:
    """A World from a world file, world YAML text, a built World, or None (an empty world)."""
    if isinstance(source, World):
        return source
    if source is None:
        source = EMPTY_WORLD
    if isinstance(source, str) and _looks_like_text(source):
        spec = WorldSpec.from_doc(load_yaml_text(source, "<world text>"))
        return World(spec, seed=seed)
    return World(load_world_spec(source), seed=seed, file=source)


class BlackboardView(MutableMapping[str, Any]):
    """The tree's blackboard by plain key (`tree.blackboard["path"]`), py_trees' root namespace."""

    def __getitem__(self, key: str) -> Any:
        try:
            return Blackboard.get("/" + key.lstrip("/"))
        except KeyError:
            raise KeyError(key) from None

    def __setitem__(self, key: str, value: Any) -> None:
        Blackboard.set("/" + key.lstrip("/"), value)

    def __delitem__(self, key: str) -> None:
        if not Blackboard.unset("/" + key.lstrip("/")):
            raise KeyError(key)

    def __iter__(self) -> Iterator[str]:
        return (key.lstrip("/") for key in blackboard.stored_keys())

    def __len__(self) -> int:
        return len(blackboard.stored_keys())


class _Tee(io.StringIO):
    """BtLog's sink: every line kept in memory, and written to the run folder's file."""

    def __init__(self, file: TextIO | None) -> None:
        super().__init__()
        self.file = file

    def write(self, text: str) -> int:
        if self.file is not None:
            self.file.write(text)
        return super().write(text)


class _Stub(Behaviour):
    """A node replaced by the test: its statuses come from a script or a callable."""

    def __init__(self, name: str, script: Sequence[str] | Callable[[], str]) -> None:
        super().__init__(name=name)
        self.script = script
        self.calls = 0

    def update(self) -> Status:
        if callable(self.script):
            answer = self.script()
        else:
            answer = self.script[min(self.calls, len(self.script) - 1)]
        self.calls += 1
        return _STATUS[_checked_status(answer)]


def _checked_status(answer: Any) -> str:
    if answer not in STATUSES:
        raise UnknownNameError(
            f"a stubbed node returns one of {', '.join(STATUSES)}, not {answer!r}",
            suggestion=best_match(str(answer), STATUSES),
        )
    return str(answer)


def stub_nodes(root: Behaviour, stubs: Mapping[str, Any]) -> Behaviour:
    """Replace each node whose type or name is a key of `stubs`; the (maybe new) root."""
    nodes = list(root.iterate())
    for key, script in stubs.items():
        if not callable(script):
            script = [script] if isinstance(script, str) else list(script)
            for answer in script:
                _checked_status(answer)
        found = [n for n in nodes if matches(key, n.name, type(n).__name__)]
        if not found:
            known = short_names((n.name, type(n).__name__) for n in nodes)
            raise UnknownNameError(
                f"no node '{key}' in the tree to stub; it has: {', '.join(known)}",
                suggestion=best_match(key, known),
            )
        for node in found:
            cls = type(type(node).__name__, (_Stub,), {"__module__": __name__})
            stub = cls(node.name, script)
            parent = node.parent
            if parent is None:
                root = stub
            elif isinstance(parent, py_trees.decorators.Decorator):
                adopt(stub)
                parent.children[0] = parent.decorated = stub
                stub.parent = parent
            else:
                parent.replace_child(node, stub)
    return root


class TreeUnderTest:
    """A built tree, its runtime (fake or a navigator's), servers and tick log."""

    def __init__(
        self,
        root: Behaviour,
        runtime: Runtime,
        *,
        period: float,
        servers: Mapping[str, FakeServer],
        stack: Any,
        log_file: TextIO | None = None,
        out_dir: Path | None = None,
    ) -> None:
        self.root = root
        self.runtime = runtime
        self.period = period
        #: The fake action servers by name (empty with a navigator's real servers).
        self.servers = dict(servers)
        self.stack = stack
        self.out_dir = out_dir
        self.ticks = 0
        self.blackboard = BlackboardView()
        self._sink = _Tee(log_file)
        self._log_file = log_file
        self._log = BtLog(self._sink, lambda: runtime.now)
        self._owner = SimpleNamespace(root=root, name="tree")
        self._log(self._owner, runtime.now)

    @property
    def now(self) -> float:
        return self.runtime.now

    @property
    def status(self) -> str:
        """The root's status in BT.CPP's words: IDLE, RUNNING, SUCCESS or FAILURE."""
        return STATUS_NAMES[self.root.status]

    def tick(self) -> str:
        """Tick once at the current sim time, then let one period pass; the tick's status."""
        self.root.tick_once()
        self.ticks += 1
        self._log(self._owner, self.runtime.now)
        status = self.status
        self.runtime.spin_for(self.period)
        return status

    def halt(self) -> None:
        """Halt the tree as bt_navigator does on a cancel (running action nodes cancel)."""
        self.root.stop(Status.INVALID)
        self._log(self._owner, self.runtime.now)

    def node(self, name: str) -> Behaviour:
        """The first node with this name (or type)."""
        nodes = list(self.root.iterate())
        for node in nodes:
            if matches(name, node.name, type(node).__name__):
                return node
        known = short_names((n.name, type(n).__name__) for n in nodes)
        raise UnknownNameError(
            f"no node '{name}' in the tree; nodes: {', '.join(known)}",
            suggestion=best_match(name, known),
        )

    @property
    def bt_log(self) -> list[dict[str, Any]]:
        """Every status change so far, as `bt_log.jsonl`'s records."""
        return [json.loads(line) for line in self._sink.getvalue().splitlines()]

    def close(self) -> None:
        if self._log_file is not None and not self._log_file.closed:
            self._log_file.close()

    def __repr__(self) -> str:
        return f"TreeUnderTest({self.root.name!r}, {self.status}, {self.ticks} ticks)"


def make_tree(
    source: str | PathLike[str],
    *,
    servers: Mapping[str, Answers] | None = None,
    nodes: Mapping[str, Any] | None = None,
    blackboard: Mapping[str, Any] | None = None,
    goal: Any = None,
    goals: Sequence[Any] | None = None,
    navigator: Any = None,
    world: str | PathLike[str] | World | None = None,
    period: float | None = None,
    main_tree: str | None = None,
    out_dir: Path | None = None,
) -> TreeUnderTest:
    """Build a tree under test (see the module doc); a bad tree is the loader's located error.

    `source` is YAML or XML text, a tree file, or a bundled tree's bare name
    (`navigate_to_pose_w_replanning_and_recovery`)."""
    if not (isinstance(source, str) and _looks_like_text(source)):
        source = find_tree(source, base_dir=Path.cwd())
    doc = load_document(source)
    if navigator is not None:
        if servers or world is not None:
            raise TypeError("a tree on a navigator uses its real servers and world")
        runtime = navigator.runtime
        stack = navigator.stack
        context = dict(navigator.bt_navigator.context)
        period = period or navigator.bt_navigator.params.bt_loop_duration / 1000.0
        fakes: dict[str, FakeServer] = {}
    else:
        runtime = Runtime(make_world(world))
        stack = FakeStack(runtime)
        context = {"runtime": runtime, "stack": stack}
        period = period or DEFAULT_PERIOD
        fakes = make_servers(runtime, doc, servers, 1.0 / period)
    for key, value in (blackboard or {}).items():
        Blackboard.set("/" + key.lstrip("/"), value)
    if goals is not None:  # as bt_navigator's NavigateThroughPoses: `goals`, and `goal` the last
        poses = [_pose(p) for p in goals]
        Blackboard.set("/goals", poses)
        Blackboard.set("/goal", poses[-1])
    if goal is not None:
        Blackboard.set("/goal", _pose(goal))
    root = build_tree(doc, main_tree=main_tree, clock=runtime.clock, context=context)
    if nodes:
        root = stub_nodes(root, nodes)
    log_file = open(out_dir / "bt_log.jsonl", "w") if out_dir is not None else None  # noqa: SIM115
    return TreeUnderTest(
        root,
        runtime,
        period=period,
        servers=fakes,
        stack=stack,
        log_file=log_file,
        out_dir=out_dir,
    )


def _pose(value: Any) -> Any:
    return value if hasattr(value, "x") or hasattr(value, "pose") else Pose2D(*value)
