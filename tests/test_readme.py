"""The README's Python examples run as printed, and give the same numbers twice."""

from __future__ import annotations

import contextlib
import io
import os
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def run_example(index: int) -> str:
    code = re.findall(r"```python\n(.*?)```", (REPO / "README.md").read_text(), re.S)[index]
    out = io.StringIO()
    cwd = os.getcwd()
    try:
        os.chdir(REPO)
        with contextlib.redirect_stdout(out):
            exec(compile(code, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    return out.getvalue()


def test_readme_world_example_runs_and_is_deterministic():
    first = run_example(0)
    assert "Pose2D" in first
    assert first == run_example(0)


@pytest.mark.slow
def test_readme_navigation_example_reaches_the_goal_untouched():
    out = run_example(1).split()
    assert out[0] == "SUCCEEDED" and out[1] == "0" and out[-1] == "0"


@pytest.mark.slow
def test_readme_navigator_example_succeeds():
    out = run_example(3).split()
    assert out[0] == "succeeded" and out[1] == "0" and out[-1] == "0"


def printed_after(marker: str) -> list[str]:
    """The lines of the first ``` block after the README line holding `marker`."""
    text = (REPO / "README.md").read_text()
    block = re.search(re.escape(marker) + r".*?```\n(.*?)```", text, re.S)
    assert block, f"no block after {marker!r} in README.md"
    return block.group(1).splitlines()


WALL = re.compile(r" in [0-9.]+ s wall \([0-9.]+x real time\)")


@pytest.mark.slow
def test_readme_demo_line_is_what_the_demo_prints(tmp_path, capsys):
    from btnav.cli import main

    claimed = printed_after("It prints one line")[0]
    assert main(["run", str(REPO / "missions" / "office_tour.yaml"), "--out", str(tmp_path)]) == 0
    printed = capsys.readouterr().out.splitlines()[0]
    assert WALL.sub("", printed) == WALL.sub("", claimed), (
        "README.md's demo line is stale: run the demo and paste what it prints"
    )


def test_readme_params_check_example_is_what_params_check_prints(tmp_path, capsys, monkeypatch):
    from btnav.cli import main

    command, claimed = printed_after("and the command exits 2:")[:2]
    name = command.split()[-1]
    nav2 = (REPO / "params" / "nav2_params.yaml").read_text()
    (tmp_path / name).write_text(
        nav2.replace("controller_frequency: 20.0", "controller_frequncy: 20.0")
    )
    monkeypatch.chdir(tmp_path)
    assert main(command.split()[2:]) == 2  # "$ btnav params check FILE"
    assert capsys.readouterr().err.strip() == claimed


def test_every_btnav_command_in_the_readme_parses_and_names_files_that_exist():
    """The shell lines a reader copies: each `btnav ...` is a command btnav has, and each
    mission, params file, tree or world it names is in the repository."""
    from btnav.cli import build_parser

    text = (REPO / "README.md").read_text()
    lines = []
    for block in re.findall(r"```bash\n(.*?)```", text, re.S):
        for line in block.replace("\\\n", " ").splitlines():
            for part in line.split("#")[0].split("&&"):
                if part.strip().startswith("btnav "):
                    lines.append(part.split()[1:])
    assert len(lines) >= 8
    parser = build_parser()
    for argv in lines:
        parser.parse_args(argv)  # an unknown command or option exits (fails the test)
        for arg in argv:
            if arg.startswith(("missions/", "params/", "worlds/", "plugins/", "trees/")):
                assert (REPO / arg).exists(), f"README names {arg}, which is not there"
