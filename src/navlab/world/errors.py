"""The world package's error for files it cannot read."""

from ..errors import NavlabError


class WorldFormatError(NavlabError):
    """A world file is malformed; the message names the file and the field."""
