"""Gazebo model folders written for a test: `NAME/model.config` and the SDF file it names."""

from __future__ import annotations

from pathlib import Path

LIDAR = """
      <sensor name="{name}" type="gpu_lidar">
        {pose}
        <update_rate>10</update_rate>
        <lidar>
          <scan><horizontal><samples>360</samples><resolution>1</resolution>
            <min_angle>-3.14159</min_angle><max_angle>3.14159</max_angle></horizontal></scan>
          <range><min>0.1</min><max>8.0</max></range>
        </lidar>
      </sensor>"""


def box_link(name: str, size: str = "0.4 0.3 0.1", pose: str = "") -> str:
    return (
        f'    <link name="{name}">{pose}\n'
        f'      <collision name="c"><geometry><box><size>{size}</size></box></geometry>'
        "</collision>\n    </link>\n"
    )


def write_model(
    root: Path, name: str, body: str, *, version: str = "1.9", model_name: str | None = None
) -> Path:
    """root/NAME/ with a model.config naming model.sdf, which holds `<model>` with `body`."""
    folder = root / name
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "model.config").write_text(
        f'<?xml version="1.0"?>\n<model>\n  <name>{name}</name>\n'
        f'  <sdf version="{version}">model.sdf</sdf>\n</model>\n'
    )
    (folder / "model.sdf").write_text(
        f'<?xml version="1.0"?>\n<sdf version="{version}">\n'
        f'  <model name="{model_name or name}">\n{body}  </model>\n</sdf>\n'
    )
    return folder / "model.sdf"


def line_of(path: Path, text: str, after: int = 0) -> int:
    """The 1-based line of the first `text` in the file past line `after`."""
    lines = path.read_text().splitlines()
    return next(i for i, line in enumerate(lines, 1) if i > after and text in line)
