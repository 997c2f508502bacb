"""The bench's error type, apart from everything that raises it (so that the
experiment, map and suite modules need not import each other for it)."""

from ..errors import NavlabError


class ExperimentError(NavlabError):
    """An experiment definition that cannot run; the message says where."""
