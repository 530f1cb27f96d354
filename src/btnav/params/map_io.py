"""Keys of Nav2's map_server (serves a map file) and map_saver (writes one)."""

from __future__ import annotations

from pydantic import Field, model_validator

from .node import NodeParams
from .schema import FieldProblem, Frame, Why, ignored


class MapServerParams(NodeParams):
    """map_server: the map a mission names wins over yaml_filename (Nav2's launch does the same)."""

    yaml_filename: str = ""
    frame_id: Frame = "map"
    topic_name: str = ignored("map", Why.TOPIC)


class MapSaverParams(NodeParams):
    """map_saver: thresholds written into a saved map's YAML."""

    free_thresh_default: float = Field(0.25, ge=0.0, le=1.0)
    occupied_thresh_default: float = Field(0.65, ge=0.0, le=1.0)
    save_map_timeout: float = ignored(2.0, Why.SERVICE, gt=0.0)
    map_subscribe_transient_local: bool = ignored(True, Why.QOS)

    @model_validator(mode="after")
    def _thresholds(self) -> MapSaverParams:
        if self.free_thresh_default >= self.occupied_thresh_default:
            raise FieldProblem(
                "free_thresh_default",
                f"free_thresh_default ({self.free_thresh_default}) must be below "
                f"occupied_thresh_default ({self.occupied_thresh_default})",
            )
        return self
