"""The error a broken robot description raises: one line naming the user's file and line."""

from __future__ import annotations

from ..core.errors import BtnavError


class DescriptionError(BtnavError):
    """A URDF, xacro or SDF description btnav cannot read (a joint to a missing link, an
    unknown xacro macro, an include that is not there, a malformed number, ...).

    `file` and `line` are those of the element in the user's own file (the xacro source,
    not the expanded URDF), so the message points where the fix goes.
    """
