"""The world package's error for files it cannot read."""


class WorldFormatError(ValueError):
    """A world file is malformed; the message names the file and the field."""
