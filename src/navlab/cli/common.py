"""Helpers shared by the ``navlab`` verbs (the only module they import from each other)."""

from __future__ import annotations

import atexit
import math
import os
import re
from typing import Any, Dict, Optional, Tuple

import click

from ..errors import EXIT_INTERRUPTED  # noqa: F401 (the verbs take it from here)
from ..wording import escaped

#: exit status for bad input (a malformed file, an unknown name, a value out of range)
EXIT_USAGE = 2
#: exit status for an unexpected failure inside navlab (a bug: please report it)
EXIT_INTERNAL = 1

#: optional packages and the extra that installs them
_EXTRAS = {"dask": "dask", "distributed": "dask", "ompl": "ompl", "pyastar2d": "bench",
           "rclpy": "ros2", "rosbags": "ros2", "nav_msgs": "ros2", "geometry_msgs": "ros2",
           "sensor_msgs": "ros2", "std_msgs": "ros2", "tf2_msgs": "ros2", "visualization_msgs": "ros2"}


class SuggestingGroup(click.Group):
    """A command group whose "No such command" names the closest verb, as click
    already does for a misspelt option ("Did you mean --seed?")."""

    def resolve_command(self, ctx, args):
        try:
            return super().resolve_command(ctx, args)
        except click.UsageError as exc:
            import difflib

            name = args[0] if args else ""
            verbs = self.list_commands(ctx)
            close = difflib.get_close_matches(name, verbs, n=1) if name not in verbs else []
            if not close:
                raise
            raise click.UsageError(f"No such command '{name}'. Did you mean '{close[0]}'?", exc.ctx) from None


class SuggestingChoice(click.Choice):
    """click's Choice whose refusal names the closest choice ("Did you mean 'diff'?"), by the rule the
    registries' names use (:func:`navlab.registry.suggest`); every choice option of ``navlab`` is one."""

    def convert(self, value, param, ctx):
        try:
            return super().convert(value, param, ctx)
        except click.BadParameter as exc:
            from ..registry import suggest

            hint = suggest(str(value), [str(c) for c in self.choices])
            if not hint:
                raise
            self.fail(f"{exc.message}{hint}", param, ctx)


class ExactNumber(click.ParamType):
    """A number as written: a whole number stays an exact int, anything else a float (as float,
    cell 2**63 - 1 came back in messages as 2**63)."""

    name = "number"

    def convert(self, value, param, ctx):
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return value
        for kind in (int, float):
            try:
                return kind(value)
            except (TypeError, ValueError):
                pass
        self.fail(f"{value!r} is not a number", param, ctx)


class FiniteNumber(click.ParamType):
    """A finite number: a coordinate or a heading (click's ``float`` lets ``nan`` and ``inf`` through, and the
    experiment or node then named a field the user never wrote: review, session 31)."""

    name = "number"
    what = "a finite number"

    def accepts(self, number: float) -> bool:
        return math.isfinite(number)

    def convert(self, value, param, ctx):
        try:
            number = float(value)
        except (TypeError, ValueError, OverflowError):
            self.fail(f"{value!r} is not a number", param, ctx)
        if not self.accepts(number):
            self.fail(f"{value!r} is not {self.what}", param, ctx)
        return number


class NonNegativeNumber(FiniteNumber):
    """A finite number of at least 0: a radius, a wait (click's ``FloatRange(min=0)`` lets ``nan`` and ``inf``
    through, and the planner then named its own field, not the flag: newcomer, session 31)."""

    what = "a finite number of at least 0"

    def accepts(self, number: float) -> bool:
        return math.isfinite(number) and number >= 0


class PositiveNumber(FiniteNumber):
    """A finite number above 0 (click's ``FloatRange(min=0, min_open=True)`` lets ``nan`` and ``inf`` through:
    ``navlab bench --max-time nan`` was blamed on the experiment file's budget; review, session 21)."""

    what = "a positive finite number"

    def accepts(self, number: float) -> bool:
        return math.isfinite(number) and number > 0


class Count(click.ParamType):
    """A whole number from ``low`` up, also written as a float (``1e5``, ``2000.0``), as
    ``--param max_iter=1e5`` and experiment files take it (:func:`navlab.limits.check_count`)."""

    name = "integer"

    def __init__(self, low: int = 1, high: Optional[int] = None) -> None:
        self.low = low
        self.high = high  # None: the count rule's own bound

    def convert(self, value, param, ctx):
        from ..limits import MAX_COUNT, check_count

        if isinstance(value, int):
            number = value
        else:
            try:
                number = int(value)
            except (TypeError, ValueError):
                try:
                    number = float(value)
                except (TypeError, ValueError):
                    self.fail(f"{value!r} is not a whole number", param, ctx)
        try:
            return check_count(param.name if param is not None else "value", number, self.low,
                               MAX_COUNT if self.high is None else self.high)
        except ValueError as exc:
            self.fail(str(exc), param, ctx)


def before_numba_import() -> None:
    """What a planning verb's process does first: import numba without PyYAML and with
    ``importlib.metadata`` deferred to its first use (``numba_start.import_numba_lean``)."""
    from ..numba_start import import_numba_lean

    import_numba_lean()


def before_first_kernel() -> None:
    """What a planning verb's process does once numba is imported, before its first kernel loads:
    cached kernels load without numba's registries (``numba_cached_loads.cached_loads_without_registries``)
    and a first use's compile says so on a terminal (``compile_clock.say_when_compiling``)."""
    from ..compile_clock import say_when_compiling
    from ..numba_cached_loads import cached_loads_without_registries

    cached_loads_without_registries()
    say_when_compiling()


#: the click context's ``meta`` key holding the exit status a verb's answer has, for when its reader goes
#: away before the output ends (:func:`status_if_output_is_cut`)
CUT_STATUS = "navlab.status_if_output_is_cut"
#: the root context's meta key: whether this process is the navlab command (``_is_the_command``)
THE_COMMAND = "navlab.the_command"


def status_if_output_is_cut(code: int) -> None:
    """The exit status to end with if standard output's reader goes away before this verb's output ends
    (``navlab plan ... | head -1``). Such a command ends quietly, status 0, as ``ls | head -1`` does; but
    ``plan`` and ``sim`` answer with their status (1: no path, not reached), and a TIMEOUT read by ``head``
    ended 0, success under ``set -o pipefail`` (attack, session 23)."""
    click.get_current_context().meta[CUT_STATUS] = code


def debug_enabled() -> bool:
    """True when ``NAVLAB_DEBUG`` is set to anything but ''/0: show Python tracebacks."""
    return os.environ.get("NAVLAB_DEBUG", "").strip() not in ("", "0")


def _one_line(text: str, limit: int = 2000) -> str:
    """``text`` on one line: whitespace runs (line breaks too) as one space, other control characters escaped
    (a file name holding ESC [31m turned the terminal red; newcomer run, session 21), cut at ``limit``."""
    text = escaped(" ".join(str(text).split()))
    return text if len(text) <= limit else text[: limit - 3] + "..."


def describe_error(exc: BaseException) -> Tuple[int, str]:
    """The exit status and the one ``Error: ...`` line the CLI prints for ``exc``.

    Bad input — navlab's own error types (:class:`navlab.NavlabError`: ``ParameterError``,
    ``WorldFormatError``, ``MapFormatError``, ``UnknownNameError``, ...), a file that
    cannot be read or written, a missing optional package, a request larger
    than memory — is the user's to fix: status 2. Anything else is a defect in
    navlab: status 1 and the exception's type, so it can be reported; that includes
    a ``ValueError`` that is not navlab's (numpy's, say), which no check of navlab's
    raised (until session 17 every ``ValueError`` was taken for bad input).
    """
    if isinstance(exc, MemoryError):
        detail = _one_line(exc) or "out of memory"
        return EXIT_USAGE, (f"Error: the request is too large for this machine's memory ({detail}); "
                            "ask for fewer iterations, cells or samples")
    if isinstance(exc, ModuleNotFoundError) and exc.name:
        top = exc.name.split(".")[0]
        if top in _EXTRAS:
            from ..extras import install_command

            return EXIT_USAGE, f"Error: this needs the optional package '{top}': {install_command(_EXTRAS[top])}"
    if isinstance(exc, OSError):
        what = exc.strerror or _one_line(exc) or type(exc).__name__
        if exc.filename is not None:
            from ..limits import short_name

            name = short_name(os.fsdecode(exc.filename))
            other = f" -> {short_name(os.fsdecode(exc.filename2))}" if exc.filename2 is not None else ""
            return EXIT_USAGE, f"Error: {name}{other}: {what}"
        return EXIT_USAGE, f"Error: {what}"
    from ..errors import NavlabError

    if isinstance(exc, NavlabError):
        return EXIT_USAGE, f"Error: {_one_line(exc) or type(exc).__name__}"
    return EXIT_INTERNAL, (f"Error: internal error: {type(exc).__name__}: {_one_line(exc, 500)} "
                           "(run with NAVLAB_DEBUG=1 for the traceback)")


def parse_params(items: Tuple[str, ...], flag: str = "--param") -> Dict[str, Any]:
    """``key=value`` pairs; values are read as YAML (numbers, lists, mappings), by the rules of every
    YAML file navlab reads (:func:`navlab.yamlio.load_value`: YAML 1.2's core schema, so ``1e-3`` is a
    number and ``010`` ten, as Nav2's yaml-cpp reads them).

    Values are passed on as read (a huge integer, ``.inf``, a list): the
    planner's or sampler's own checks reject what is out of range, with a
    message naming the parameter. An empty value is refused here (it read as None).
    """
    if not items:
        return {}
    import yaml  # only when a --param is given: PyYAML's import is ~25 ms of a planning command's start

    from ..yamlio import load_value

    out: Dict[str, Any] = {}
    for item in items:
        key, sep, value = item.partition("=")
        key = key.strip()
        if key in out:
            raise click.BadParameter(f"'{key}' is given twice", param_hint=flag)
        if not sep or not key:
            raise click.BadParameter(f"expected key=value, got {item!r}", param_hint=flag)
        if not value.strip():
            raise click.BadParameter(f"'{key}' has no value: give one after '=' (or leave the --param out for "
                                     f"the default)", param_hint=flag)
        try:
            out[key] = load_value(value)
        except yaml.YAMLError as exc:  # (the problem alone: the mark repeats the value just given)
            problem = getattr(exc, "problem", None) or exc
            raise click.BadParameter(f"cannot read the value of '{key}': {_one_line(problem, 300)}",
                                     param_hint=flag) from None
        except RecursionError:
            raise click.BadParameter(f"the value of '{key}' is nested too deeply", param_hint=flag) from None
        except ValueError as exc:  # (a constructor of PyYAML's own that raises one)
            raise click.BadParameter(f"cannot read the value of '{key}': {_one_line(exc, 300)}",
                                     param_hint=flag) from None
    return out


def note_unused_grid_settings(algorithm: str, settings: Dict[str, Any], spelled) -> None:
    """Each of :func:`navlab.grid.planner.unused_settings`' lines on stderr."""
    from ..grid.planner import unused_settings

    for line in unused_settings(algorithm, settings, spelled):
        click.echo(line, err=True)


def check_output_file(path: str, flag: str, suffix: str = "") -> None:
    """Refuse, before any work, an output file whose folder is missing or not writable, or (with ``suffix``,
    the one format it is written in) whose name does not end in ``suffix``."""
    import os

    folder = os.path.dirname(os.path.abspath(path)) or "."
    if os.path.isdir(path):
        raise click.BadParameter(f"{path} is a folder; give a file name", param_hint=flag)
    if suffix and not path.lower().endswith(suffix):
        # (--gif out.png wrote GIF data into out.png without a word: newcomer, session 30)
        raise click.BadParameter(f"it is written as {suffix[1:].upper()}: give a name ending in {suffix}, got {path}",
                                 param_hint=flag)
    if not os.path.isdir(folder):
        raise click.BadParameter(f"cannot write {path}: the folder {folder} does not exist", param_hint=flag)
    if not os.access(folder, os.W_OK):
        raise click.BadParameter(f"cannot write {path}: the folder {folder} is not writable", param_hint=flag)


def check_figure_file(path: str, flag: str) -> None:
    """Refuse, before any work, a figure that cannot be written: as :func:`check_output_file`, and a
    suffix matplotlib has no format for (``navlab plan --plot nosuchdir/p.png`` or ``--plot out.txt``
    planned for 11 s and then printed only the error, the plan lost: newcomer, session 31). No
    suffix is matplotlib's default format (PNG)."""
    import os

    check_output_file(path, flag)
    suffix = os.path.splitext(path)[1][1:].lower()
    if suffix:
        from ..viz.save import figure_formats

        formats = figure_formats()
        if suffix not in formats:
            names = ["." + f for f in sorted(formats)]
            raise click.BadParameter(f"no figure format is named .{suffix}: give a name ending in "
                                     f"{', '.join(names[:-1])} or {names[-1]}, got {path}", param_hint=flag)


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


#: a number with letters after it ("1.5x", "90deg", "90°"): what a mistyped heading looks like, and
#: no source's name (scenes are words, files have an extension or a path)
_MISTYPED_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?[A-Za-z°]{1,4}")


def _mistyped_number(token: str) -> bool:
    return _MISTYPED_NUMBER.fullmatch(token) is not None


class PointOrPoseOption(click.Option):
    """An option taking ``X Y`` or a pose ``X Y THETA`` (metres, radians):
    click's options take a fixed number of values, so the parser is told to
    take a third one when the token after ``Y`` is a number. The value is a
    tuple of 2 or 3 floats (None when the option is not given)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("metavar", "X Y [THETA]")
        super().__init__(*args, type=str, **kwargs)

    def add_to_parser(self, parser: Any, ctx: click.Context) -> None:
        super().add_to_parser(parser, ctx)
        for name in self.opts:
            option = parser._long_opt.get(name) or parser._short_opt.get(name)
            take = option.process

            def process(value: str, state: Any, take=take) -> None:
                values = [value]
                while len(values) < 3 and state.rargs and (_is_number(state.rargs[0]) or
                                                           len(values) == 2 and _mistyped_number(state.rargs[0])
                                                           or len(values) == 1 and not state.rargs[0].startswith("-")):
                    # (a mistyped heading, "1.5x" or "90deg", is taken too, so the error names the pose: left
                    # behind it was "unexpected extra argument"; and a Y that is not a number, so "--start 1 abc"
                    # is not echoed as "got '1'": newcomer, session 31)
                    values.append(state.rargs.pop(0))
                take(" ".join(values), state)

            option.process = process

    def type_cast_value(self, ctx: click.Context, value: Any) -> Any:
        if value is None:
            return None
        tokens = str(value).split()
        if len(tokens) not in (2, 3) or not all(_is_number(t) for t in tokens):
            raise click.BadParameter(f"expected X Y or X Y THETA (numbers), got {str(value)!r}", ctx=ctx, param=self)
        numbers = tuple(float(t) for t in tokens)
        for token, number in zip(tokens, numbers):
            if math.isinf(number) and "inf" not in token.lower():  # float() made 10**400 written out inf
                digits = f"{token[:12]}... ({len(token)} characters)" if len(token) > 24 else token
                raise click.BadParameter(f"{digits} is past the largest number a float holds", ctx=ctx, param=self)
        if not all(math.isfinite(n) for n in numbers):  # (the planner's "goal x must be finite" named no flag)
            raise click.BadParameter(f"coordinates and headings must be finite, got {str(value)!r}", ctx=ctx,
                                     param=self)
        # (a heading beyond ±2π is legal, but more often degrees: the planner's HeadingWarning says so,
        # printed as a note by the command: navlab.cli.heading_notes)
        return numbers


def end_at_ctrl_c(code, ctx=None) -> None:
    """Once the command has said its last (its output written, its exit status ``code`` chosen, after Ctrl-C
    too), a Ctrl-C ends the process at once with that status, its output flushed: one landing while the
    interpreter shut down ended it by the signal, with no message and no status of its own (attack, session
    29: 18 of 18 Ctrl-Cs 0-20 ms after the last line; and a second Ctrl-C after navlab bench's resume line),
    and ignoring it would leave a hang at exit (a pool's or a Dask cluster's join) with no way out but kill.
    Only in the navlab command's own process (``ctx``: a verb's context, whose root says it, THE_COMMAND;
    None: the caller knows): a program calling :func:`main` keeps its handlers. A verb arms it before its
    last line (navlab bench's resume line: a second Ctrl-C landing after it ended the run by the signal)."""
    import signal
    import sys
    import threading

    if ctx is not None and not ctx.find_root().meta.get(THE_COMMAND):
        return

    status = code if isinstance(code, int) else 0 if code is None else 1  # (as sys.exit reads its argument)

    def end(signum, frame) -> None:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError, RuntimeError, AttributeError):
                pass  # gone, closed, or being written this very moment
        os._exit(status)

    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, end)
        # Late in the shutdown Python puts SIG_DFL back for a handler of its own, and a Ctrl-C there ended the
        # process by the signal after all (exit -2 under the resume line, 1 in 6 double Ctrl-Cs at load 6);
        # an ignored SIGINT stays ignored. Set in an exit handler: the threads' joins before it (a pool's)
        # still end at a Ctrl-C, by ``end``.
        atexit.unregister(_ignore_ctrl_c)
        atexit.register(_ignore_ctrl_c)


def _ignore_ctrl_c() -> None:
    """:func:`end_at_ctrl_c`'s exit handler."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
