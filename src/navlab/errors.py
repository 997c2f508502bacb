"""navlab's error types for bad input: one family, each a ``ValueError``.

Every check on what a user gives navlab (an argument, a setting, a file, a
name) raises a :class:`NavlabError` whose message names the field, so a
caller can tell a refused input from a fault inside navlab or a library
(``except navlab.NavlabError``), and code that catches ``ValueError`` keeps
working. The subclasses say which kind of input:

- :class:`ParameterError`: an argument or setting (out of range, of the wrong
  type, not finite, inconsistent with another);
- ``WorldFormatError``, ``MapFormatError``, ``MotionFormatError``,
  ``FootprintError``, ``CostmapError``, ``ExperimentError``: a world, map,
  motion, footprint, costmap or experiment definition (a file's messages
  name the file);
- ``UnknownNameError`` (also a ``KeyError``): a name no registry holds, with
  the valid names;
- ``MissingQueryError``, ``NoPathError``: a query without its start or goal,
  a simulation with nothing to follow.

This module imports nothing of navlab's, so every module may raise them.
"""

from __future__ import annotations


class NavlabError(ValueError):
    """Input navlab refuses; the message names the field (and the file, for a file)."""


class ParameterError(NavlabError):
    """An argument or setting navlab refuses: out of range, of the wrong type, not finite, or at odds
    with another; the message names it."""


#: the exit status after Ctrl-C (128 + SIGINT, as shells report it)
EXIT_INTERRUPTED = 130


def interrupted_by_ctrl_c(exc: BaseException) -> bool:
    """Whether ``exc`` is a Ctrl-C: a ``KeyboardInterrupt``, or the ``SystemError`` Python raises in its
    place when the interrupt's handler ran inside a C function that then returned a result anyway ("...
    returned a result with an exception set", the interrupt its ``__cause__``): numba's dispatcher of a
    compiled kernel did so (fuzz test_real_command_ctrl_c_is_one_line, a full local run under load,
    session 29), and the command printed an internal error and exited 1 instead of 130; a bench trial
    recorded it as an ERROR row and the run went on. The SystemErrors can nest, each the cause of the next
    (three deep, an RRT* plan interrupted in the nearest-neighbour grid's build kernel: 5 of 1 200 interrupts
    in a probe; fresh-clone CI, session 32), so the chain of causes is followed through them."""
    for _ in range(16):  # (a chain of causes cannot loop, but a bound costs nothing)
        if not isinstance(exc, SystemError):
            break
        exc = exc.__cause__
    return isinstance(exc, KeyboardInterrupt)
