"""`run.gif`, the `gif` output: the run as an animation, as RViz would have shown it.

`outputs: [report, gif]` in a mission, or `btnav run MISSION --gif`. Each frame shows
the map (or, with no map, the world's walls and obstacles), the robot's footprint
where it truly is, the latest scan, the global plan, the local plan (MPPI's optimal
trajectory, DWB's best trajectory, Regulated Pure Pursuit's path to its lookahead
point, or what a controller's `local_plan` gives), the shapes plugins draw of
themselves (`core.drawing`), AMCL's particle cloud or SLAM's map as it grows, the ground-truth path so far
and, in the top-left corner, the sim time, the running BT action and the waypoint.
The last frame holds the run's result.

A `RunRecorder` (added in `start`) snapshots what frames need at `frame_rate` Hz of
sim time, at most `max_frames` (a long run is thinned evenly). Frames are drawn with
matplotlib's Agg canvas, headless: the static background is drawn once and only the
moving artists are redrawn onto it (blitting). They are mapped to one palette (taken
from a few sample frames) and streamed to the file with pillow, each frame stored as
the box that changed with its unchanged pixels transparent, so a tour stays small
and only two frames are ever held in memory.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from ..core.errors import BtnavError
from ..mission.outputs import RunOutput
from ..mission.run_status import format_status
from ..plugins import register
from .plugin_drawings import DrawableArtists, legend_handles
from .run_plot import GOAL_COLOR, PATH_COLOR, PLAN_COLOR
from .run_recorder import RunRecorder, Snapshot
from .world_plot import MOVING_COLOR, ROBOT_COLOR, SCAN_COLOR, STATIC_COLOR, _matplotlib

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from PIL import Image

LOCAL_PLAN_COLOR = "#e377c2"
#: Not run.png's orange: moving obstacles are orange here too.
PARTICLE_COLOR = "#7e3fbf"
SLAM_MAP_LABEL = "SLAM map"
#: Pixels at the bottom for the legend.
LEGEND_PX = 26
DPI = 80
#: Sample frames the palette is taken from.
PALETTE_SAMPLES = 6
#: The palette index left out of the palette: pixels unchanged since the last frame.
TRANSPARENT = 255


def _pillow() -> Any:
    try:
        from PIL import GifImagePlugin, Image
    except ImportError:
        raise BtnavError(
            "run.gif needs pillow, which comes with the viz extra: pip install 'btnav[viz]'"
        ) from None
    return Image, GifImagePlugin


@register("output", "gif")
class RunGif:
    """Writes `run.gif`; needs matplotlib and pillow (the viz extra), checked before the run."""

    files = ("run.gif",)
    #: Frames per second of sim time, and the most frames a GIF holds.
    frame_rate = 4.0
    max_frames = 600
    #: Milliseconds each frame shows (50 ms at 4 Hz: five times real time); the last holds.
    frame_ms = 50
    end_ms = 2000
    #: The map's longer side, in pixels (the legend's band comes on top).
    size_px = 720

    def __init__(self) -> None:
        _matplotlib()
        _pillow()
        self.recorder: RunRecorder | None = None

    def start(self, nav: Any, out_dir: Path) -> None:
        self.recorder = RunRecorder(nav, self.frame_rate, self.max_frames)
        nav.runtime.add(self.recorder, rate=self.frame_rate)

    def write(self, run: RunOutput) -> None:
        if self.recorder is None:  # not started: a run's plugins always are
            raise BtnavError("the gif output was not started with the run")
        frames = self.recorder.close(run.report.status)
        durations = [self.frame_ms] * (len(frames) - 1) + [self.end_ms]
        scene = GifScene(
            run, self.recorder.slam, self.size_px, [d for f in frames for d in f.drawings]
        )
        with open(run.out_dir / self.files[0], "wb") as fp:
            write_gif(fp, scene.render(frames), durations, scene.palette(frames))


class GifScene:
    """The figure of a run's frames: a static background, and the artists each frame moves."""

    def __init__(
        self, run: RunOutput, slam: bool, size_px: int, drawn: list[Any] | None = None
    ) -> None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        nav = run.navigator
        world = nav.world
        (x0, y0), (x1, y1) = world.bounds
        margin = 0.02 * max(x1 - x0, y1 - y0)
        self.xlim, self.ylim = (x0 - margin, x1 + margin), (y0 - margin, y1 + margin)
        w, h = self.xlim[1] - self.xlim[0], self.ylim[1] - self.ylim[0]
        scale = size_px / max(w, h)
        width, height = round(w * scale), round(h * scale)
        self.legend_rows = 1 if width >= 600 else 2  # a tall world: the legend on two rows
        band = LEGEND_PX * self.legend_rows
        self.fig = Figure(figsize=(width / DPI, (height + band) / DPI), dpi=DPI)
        self.canvas = FigureCanvasAgg(self.fig)
        ax = self.ax = self.fig.add_axes((0, band / (height + band), 1, height / (height + band)))
        ax.set_axis_off()
        self.track = run.track
        self.mission = run.mission.name
        grid = nav.stack.map_server.map
        _draw_background(ax, world, None if slam else grid, faint=slam)
        for x, y, _yaw in run.mission.spec.task.poses:
            ax.plot(x, y, marker="*", color=GOAL_COLOR, markersize=10, zorder=8)
        self.drawables = DrawableArtists(ax)
        self.artists = _moving_artists(ax, world, slam, nav.runtime.localizer, self.drawables)
        self._legend(slam, legend_handles(drawn or []))
        ax.set_xlim(*self.xlim)  # the images and markers above moved them
        ax.set_ylim(*self.ylim)
        ax.set_aspect("equal", adjustable="datalim")
        self.canvas.draw()
        self.background = self.canvas.copy_from_bbox(self.fig.bbox)
        self.corner = CornerText()
        self._map_shown: tuple[Any, np.ndarray | None] = (None, None)

    def _legend(self, slam: bool, drawn: list[Any]) -> None:
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch

        a = self.artists
        handles = [
            Patch(facecolor=ROBOT_COLOR, alpha=0.6, label="robot"),
            Line2D([], [], color=PATH_COLOR, label="path (ground truth)"),
            Line2D([], [], color=PLAN_COLOR, linestyle="-.", label="global plan"),
            Line2D([], [], color=LOCAL_PLAN_COLOR, linewidth=2, label="local plan"),
            Line2D([], [], color=SCAN_COLOR, marker=".", linestyle="none", label="scan"),
        ]
        if "particles" in a:
            handles.append(
                Line2D(
                    [], [], color=PARTICLE_COLOR, marker=".", linestyle="none", label="particles"
                )
            )
        if slam:
            handles.append(Patch(facecolor="#333333", label=SLAM_MAP_LABEL))
        handles.append(Line2D([], [], color=GOAL_COLOR, marker="*", linestyle="none", label="goal"))
        handles += drawn
        self.fig.legend(
            handles=handles,
            loc="lower center",
            ncol=-(-len(handles) // self.legend_rows),
            fontsize=7,
            frameon=False,
            handlelength=1.5,
            columnspacing=1.0,
            borderaxespad=0.3,
        )

    def palette(self, frames: list[Snapshot]) -> Image.Image:
        """One palette of 255 colours for every frame, from a few frames spread over the run."""
        Image, _ = _pillow()
        picks = np.unique(np.linspace(0, len(frames) - 1, PALETTE_SAMPLES).round().astype(int))
        montage = np.concatenate([self.draw(frames[i]) for i in picks], axis=0)
        quantized = Image.fromarray(montage).quantize(
            colors=TRANSPARENT, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE
        )
        palette = Image.new("P", (1, 1))
        palette.putpalette(quantized.getpalette()[: 3 * TRANSPARENT])
        return palette

    def render(self, frames: Iterable[Snapshot]) -> Iterator[np.ndarray]:
        for snap in frames:
            yield self.draw(snap)

    def draw(self, snap: Snapshot) -> np.ndarray:
        """The frame of `snap` as an (H, W, 3) uint8 RGB array (a copy)."""
        a, ax = self.artists, self.ax
        x, y, yaw = snap.robot
        a["robot"].set_xy(a["outline"] @ _rotation(yaw).T + (x, y))
        a["heading"].set_data(
            [x, x + a["size"] * 1.3 * math.cos(yaw)], [y, y + a["size"] * 1.3 * math.sin(yaw)]
        )
        for name in ("scan", "plan", "local_plan"):
            a[name].set_data(*getattr(snap, name).T)
        upto = np.searchsorted(self.track[:, 0], snap.time, side="right") if len(self.track) else 0
        a["path"].set_data(self.track[:upto, 1], self.track[:upto, 2])
        if "particles" in a:
            cloud = snap.particles if snap.particles is not None else np.zeros((0, 2))
            a["particles"].set_data(*cloud.T)
        if "slam_map" in a:
            shown = snap.slam_map
            a["slam_map"].set_visible(shown is not None)
            if shown is not None and shown is not self._map_shown[0]:  # a new map: recolour
                self._map_shown = (shown, map_rgba(shown.data, unknown_alpha=0))
                a["slam_map"].set_data(self._map_shown[1])
                a["slam_map"].set_extent(shown.extent)
        a["movers"].set_verts(snap.movers)
        self.drawables.show(snap.drawings)
        self.canvas.restore_region(self.background)
        for artist in a["draw_order"]:
            ax.draw_artist(artist)
        what = [snap.result] if snap.result is not None else list(snap.actions)
        status = f"{self.mission}\n{format_status(snap.time, None, what, snap.waypoint)}"
        px, py = ax.transData.transform((x, y))  # the robot, in pixels from the bottom left
        rgb = np.asarray(self.canvas.buffer_rgba())[:, :, :3]
        return self.corner.stamp(rgb, status, avoid=(px, rgb.shape[0] - py))


class CornerText:
    """The text in the top-left corner (top-right while the robot is under it), stamped onto
    a frame with pillow: matplotlib lays text out again on every draw, which would cost
    more than the rest of a frame."""

    def __init__(self, size: int = 12) -> None:
        from matplotlib import font_manager
        from PIL import ImageFont

        self.font = ImageFont.truetype(font_manager.findfont("DejaVu Sans Mono"), size)

    def stamp(self, rgb: np.ndarray, text: str, avoid: tuple[float, float]) -> np.ndarray:
        """A copy of `rgb` (H, W, 3) with `text` in a white box, away from pixel `avoid`."""
        from PIL import Image, ImageDraw

        image = Image.fromarray(np.ascontiguousarray(rgb))
        draw = ImageDraw.Draw(image)
        at = (10, 8)
        x0, y0, x1, y1 = draw.multiline_textbbox(at, text, font=self.font)
        if x0 - 40 <= avoid[0] <= x1 + 40 and avoid[1] <= y1 + 40:  # 40 px: the robot and more
            at = (image.width - 10 - (x1 - x0), 8)
            x0, y0, x1, y1 = draw.multiline_textbbox(at, text, font=self.font)
        draw.rounded_rectangle((x0 - 5, y0 - 4, x1 + 5, y1 + 4), 4, fill="white", outline="#999999")
        draw.multiline_text(at, text, font=self.font, fill="black")
        return np.asarray(image)


def _rotation(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s], [s, c]])


def map_rgba(data: np.ndarray, *, unknown_alpha: int = 255) -> np.ndarray:
    """An occupancy grid (int8: -1 unknown, 0 free .. 100 occupied) as an RGBA image, row 0
    at the origin: free white, occupied black, unknown grey (see-through by `unknown_alpha`)."""
    v = np.asarray(data, dtype=np.int16)
    grey = np.where(v < 0, 205, 254 - (np.clip(v, 0, 100) * 254) // 100).astype(np.uint8)
    alpha = np.where(v < 0, unknown_alpha, 255).astype(np.uint8)
    return np.stack([grey, grey, grey, alpha], axis=-1)


def _draw_background(ax: Axes, world: Any, grid: Any, *, faint: bool) -> None:
    """What does not move: the floor, then the map, or else the static walls and obstacles
    (faint under a SLAM map, which is drawn over them as it grows)."""
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle, Polygon, Rectangle

    from ..sim.scene import solids_geometry

    (x0, y0), (x1, y1) = world.bounds
    ax.add_patch(
        Rectangle((x0, y0), x1 - x0, y1 - y0, facecolor="#f7f7f2", edgecolor="#bbbbbb", zorder=0)
    )
    if grid is not None:
        res = grid.resolution
        gx, gy = grid.origin.x, grid.origin.y
        extent = (gx, gx + grid.width * res, gy, gy + grid.height * res)
        ax.imshow(
            map_rgba(grid.data), origin="lower", extent=extent, interpolation="nearest", zorder=0.5
        )
        return
    static = solids_geometry([s for s in world.solids if s.moves is None])
    patches = [Polygon(p, closed=True) for p in static.polygons]
    patches += [Circle((cx, cy), r) for cx, cy, r in static.circles]
    alpha = 0.3 if faint else 1.0
    ax.add_collection(
        PatchCollection(patches, color=STATIC_COLOR, alpha=alpha, linewidth=0.5, zorder=2)
    )


def _moving_artists(
    ax: Axes, world: Any, slam: bool, localizer: Any, drawables: DrawableArtists
) -> dict[str, Any]:
    """The artists a frame updates, animated (left out of the background), and their order."""
    from matplotlib.collections import PolyCollection
    from matplotlib.patches import Polygon

    fp = world.spec.robot.footprint
    if fp.radius is not None:
        angles = np.linspace(0.0, 2.0 * np.pi, 32, endpoint=False)
        outline = fp.radius * np.stack([np.cos(angles), np.sin(angles)], axis=-1)
    else:
        outline = np.asarray(fp.polygon, dtype=float)
    a: dict[str, Any] = {"outline": outline, "size": float(np.hypot(*outline.T).max())}
    if slam:
        a["slam_map"] = ax.imshow(
            np.zeros((1, 1, 4), np.uint8), origin="lower", interpolation="nearest", zorder=1
        )
    a["movers"] = ax.add_collection(PolyCollection([], color=MOVING_COLOR, zorder=2))
    a["plan"] = ax.plot([], [], color=PLAN_COLOR, linestyle="-.", linewidth=1.2, zorder=3)[0]
    a["path"] = ax.plot([], [], color=PATH_COLOR, linewidth=1.8, zorder=4)[0]
    if getattr(type(localizer), "particles", None) is not None:
        a["particles"] = ax.plot([], [], ".", color=PARTICLE_COLOR, markersize=2, zorder=5)[0]
    a["local_plan"] = ax.plot([], [], color=LOCAL_PLAN_COLOR, linewidth=2.0, zorder=5.5)[0]
    a["scan"] = ax.plot([], [], ".", color=SCAN_COLOR, markersize=2.5, zorder=6)[0]
    a["robot"] = ax.add_patch(
        Polygon(
            outline, closed=True, facecolor=ROBOT_COLOR, edgecolor="#0b2f6b", alpha=0.6, zorder=7
        )
    )
    a["heading"] = ax.plot([], [], color="#0b2f6b", linewidth=1.5, zorder=7.5)[0]
    a["draw_order"] = sorted(
        [*(v for k, v in a.items() if k not in ("outline", "size")), *drawables.artists],
        key=lambda v: v.get_zorder(),
    )
    for artist in a["draw_order"]:
        artist.set_animated(True)
    return a


def write_gif(
    fp: IO[bytes], frames: Iterable[np.ndarray], durations: list[int], palette: Image.Image
) -> int:
    """Stream RGB `frames` into a looping GIF on `palette` (255 colours); returns the frames
    written. A frame is stored as the box that changed since the last one, its unchanged
    pixels transparent; a frame that changed nothing lengthens the one before."""
    Image, GifImagePlugin = _pillow()
    previous: np.ndarray | None = None
    pending: tuple[Image.Image, tuple[int, int], dict[str, Any]] | None = None
    written = 0
    for n, rgb in enumerate(frames):
        index = np.asarray(Image.fromarray(rgb).quantize(palette=palette, dither=Image.Dither.NONE))
        if previous is None:
            first = _p_image(Image, index, palette)
            header, _ = GifImagePlugin.getheader(first, None, {"loop": 0, "optimize": False})
            fp.write(b"".join(header))
            pending = (first, (0, 0), {"duration": durations[n]})
        else:
            changed = index != previous
            if not changed.any():
                pending[2]["duration"] += durations[n]
                continue
            rows, cols = np.flatnonzero(changed.any(axis=1)), np.flatnonzero(changed.any(axis=0))
            box = (slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1))
            delta = np.where(changed[box], index[box], TRANSPARENT).astype(np.uint8)
            written += _flush(fp, GifImagePlugin, pending)
            info = {"duration": durations[n], "transparency": TRANSPARENT, "disposal": 1}
            pending = (_p_image(Image, delta, palette), (int(cols[0]), int(rows[0])), info)
        previous = index
    if pending is not None:
        written += _flush(fp, GifImagePlugin, pending)
    fp.write(b";")
    return written


def _p_image(Image: Any, index: np.ndarray, palette: Image.Image) -> Image.Image:
    im = Image.frombytes(
        "P", (index.shape[1], index.shape[0]), np.ascontiguousarray(index).tobytes()
    )
    im.putpalette(palette.getpalette())
    return im


def _flush(
    fp: IO[bytes], GifImagePlugin: Any, frame: tuple[Any, tuple[int, int], dict[str, Any]]
) -> int:
    im, offset, info = frame
    fp.write(b"".join(GifImagePlugin.getdata(im, offset, **info)))
    return 1
