"""Every command the README and docs/*.md show runs as written.

Each fenced ``bash`` or ``python`` block is collected in document order. The
blocks of one file run in that order in one fresh folder ``work/`` with the
repository's ``../shared`` linked beside it as ``../shared`` (commands that
need it are skipped, with the reason, when the repository has no
``../shared``). A ``bash`` block is split into commands (a trailing ``\\``
continues a line; ``#`` comments are dropped); each runs with ``bash -c`` and
must exit 0. A ``python`` block runs as one program.

What a command should do differently is said in the document itself, in an
HTML comment (invisible when the page is rendered) anywhere before the block
it applies to::

    <!-- doc-test
    navlab sim trap --robot omni3 | exit 1
    navlab bench --suite samplers | add --trials 2 --out runs/samplers
    navlab bench mine.yaml --executor dask | skip: needs a Dask scheduler at that address
    navlab ros | ros
    * | skip: the Quick start's install commands, which .ci/run runs itself
    -->

The left side is the start of a command (``*`` is every command of the
block); the right side is one of

``exit N``
    the exit status the text promises (1: a run that ends without reaching
    its goal, which the text says);
``add FLAGS``
    a long command (a study of hundreds of runs) runs with these flags added:
    a smaller study through the same code, so it still proves the command
    parses, starts and finishes;
``ros [FLAGS]``
    the command needs the ros2 extra: it runs in a private network namespace
    as tests/ros does, and is skipped when the extra is missing; FLAGS, if
    given, are added as ``add`` does (a shorter drive through the same nodes);
``ros-script`` (for ``*``)
    the whole block is one script in one private network namespace (a node
    started with ``&`` and a command that talks to it);
``serve SECONDS``
    a ROS node that runs until stopped: once it has logged its first line
    (it is up), it must still be running SECONDS later, and then end cleanly
    (exit 0) on Ctrl-C (SIGINT);
``needs MODULE [FLAGS]``
    an optional extra: skipped, saying so, when MODULE cannot be imported;
    FLAGS, if given, are added as ``add`` does;
``skip: REASON``
    not run, for the reason given (an address on someone else's network, a
    call signature rather than a program).

The rule: nothing is skipped for being slow (it is reduced with ``add``), and
a command that is not run says why in the document.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import os
import re
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

import pytest

from ros_helpers import can_unshare, ros_env

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared"
DOCUMENTS = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
FENCE = re.compile(r"^([ \t]*)```(\w*)[^\n]*\n(.*?)^[ \t]*```", re.S | re.M)  # list items indent theirs
DIRECTIVES = re.compile(r"<!--\s*doc-test\s*\n(.*?)-->", re.S)
#: a hang detector, not a speed limit: a fresh clone's first run compiles every kernel a command uses (a few
#: minutes of CPU for the Hybrid A* and Reeds–Shepp commands), and an outside run at load 8-16 took over 240 s
TIMEOUT_S = 600


@dataclasses.dataclass
class Command:
    document: str
    line: int
    lang: str
    text: str
    action: str = "run"  # run | exit | add | ros | skip
    argument: str = ""

    def __str__(self) -> str:
        return f"{self.document}:{self.line}: {self.text.splitlines()[0][:90]}"


def _split_shell(block: str, first_line: int) -> List[Tuple[int, str]]:
    """The commands of a bash block with their line numbers (continuations joined, comments dropped)."""
    out: List[Tuple[int, str]] = []
    pending, start = "", first_line
    for k, raw in enumerate(block.splitlines()):
        line = raw.rstrip()
        if not pending:
            start = first_line + k
        if line.endswith("\\"):
            pending += line[:-1] + " "
            continue
        command = _strip_comment(pending + line).strip()
        pending = ""
        if command:
            out.append((start, command))
    return out


def _strip_comment(line: str) -> str:
    """The line without a trailing ``# comment`` (a ``#`` inside quotes or a word stays)."""
    quote = ""
    for k, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = ""
        elif ch in "'\"":
            quote = ch
        elif ch == "#" and (k == 0 or line[k - 1].isspace()):
            return line[:k]
    return line


def _directives(text: str) -> Dict[str, str]:
    rules: Dict[str, str] = {}
    for body in DIRECTIVES.findall(text):
        for raw in body.splitlines():
            if "|" in raw:
                left, right = raw.split("|", 1)
                rules[left.strip()] = right.strip()
    return rules


def collect(document: Path) -> List[Command]:
    text = document.read_text(encoding="utf-8")
    name = str(document.relative_to(ROOT))
    commands: List[Command] = []
    for match in FENCE.finditer(text):
        lang = match.group(2)
        if lang not in ("bash", "sh", "python"):
            continue
        first = text[:match.start(3)].count("\n") + 1
        body = textwrap.dedent(match.group(3))
        # directives written before this block (later ones override earlier ones)
        rules = _directives(text[:match.start()][-4000:])
        block_rule = _block_rule(text, match.start())
        if lang == "python" or block_rule == "ros-script":
            items = [(first, body)]
        else:
            items = _split_shell(body, first)
        for line, command in items:
            cmd = Command(name, line, lang, command)
            rule = block_rule or _matching_rule(rules, command)
            if rule:
                verb, _, arg = rule.partition(" ")
                verb = verb.rstrip(":")
                cmd.action, cmd.argument = verb, arg.strip()
            commands.append(cmd)
    return commands


def _block_rule(text: str, block_start: int) -> Optional[str]:
    """A ``* | ...`` rule in the comment right before this block (only there)."""
    before = text[:block_start].rstrip()
    if not before.endswith("-->"):
        return None
    comment = before[before.rfind("<!--"):]
    for raw in comment.splitlines():
        if "|" in raw and raw.split("|", 1)[0].strip() == "*":
            return raw.split("|", 1)[1].strip()
    return None


def _matching_rule(rules: Dict[str, str], command: str) -> Optional[str]:
    best = None
    for prefix, rule in rules.items():
        if prefix != "*" and command.startswith(prefix) and (best is None or len(prefix) > len(best[0])):
            best = (prefix, rule)
    return None if best is None else best[1]


def _navlab_env(tmp: Path) -> Dict[str, str]:
    env = os.environ.copy()
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    env.update(MPLBACKEND="Agg", PYTHONUNBUFFERED="1", NO_COLOR="1", HOME=str(tmp / "home"))
    env.pop("NAVLAB_DEBUG", None)
    return env


def _command_line(cmd: Command, env: Dict[str, str]) -> Tuple[List[str], Dict[str, str]]:
    if cmd.lang == "python":
        args = [sys.executable, "-c", cmd.text]
    else:
        args = ["bash", "-c", " ".join(filter(None, (cmd.text, _added_flags(cmd))))]
    if cmd.action in ("ros", "ros-script", "serve"):
        # a domain of its own per document too, for machines where unshare is refused
        domain = 40 + [str(d.relative_to(ROOT)) for d in DOCUMENTS].index(cmd.document)
        env = dict(env, **{k: v for k, v in ros_env(domain).items() if k.startswith(("ROS_", "RMW_"))})
        if can_unshare():
            args = ["unshare", "-n", "sh", "-c", 'ip link set lo up && exec "$@"', "sh", *args]
    return args, env


def _added_flags(cmd: Command) -> str:
    """The flags a rule adds to the command: ``add``'s and ``ros``'s argument, and what follows the
    module that ``needs`` names (``needs ompl --trials 2``)."""
    if cmd.action in ("add", "ros"):
        return cmd.argument
    if cmd.action == "needs":
        return cmd.argument.partition(" ")[2].strip()
    return ""


def _needed_module(cmd: Command) -> str:
    return cmd.argument.partition(" ")[0]


def _run(cmd: Command, cwd: Path, env: Dict[str, str]) -> subprocess.CompletedProcess:
    args, env = _command_line(cmd, env)
    if cmd.action != "serve":
        return subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, timeout=TIMEOUT_S)
    # a node: up (its first log line), still up SECONDS later, then a clean end on Ctrl-C
    proc = subprocess.Popen(args, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines: List[str] = []
    reader = threading.Thread(target=lambda: lines.extend(proc.stdout), daemon=True)
    reader.start()
    deadline = time.monotonic() + TIMEOUT_S  # a loaded machine may take long to import and start ROS
    while not lines and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.1)
    try:
        proc.wait(timeout=float(cmd.argument))
        reader.join(5)
        return subprocess.CompletedProcess(args, f"ended by itself with {proc.returncode}", "".join(lines), "")
    except subprocess.TimeoutExpired:
        up = bool(lines)
        proc.send_signal(signal.SIGINT)
        proc.wait(timeout=30)
        reader.join(5)
        status = proc.returncode if up else f"printed nothing in {TIMEOUT_S} s"
        return subprocess.CompletedProcess(args, status, "".join(lines), "")


def _suite_on_missing_data(text: str) -> bool:
    """Whether ``text`` runs a ``navlab bench`` suite whose data is not here (grid-vs-rrt-maps reads
    the Moving AI maps in ../shared without naming the folder: a newcomer's clone failed on it)."""
    from navlab.bench.errors import ExperimentError
    from navlab.bench.suites import find_suite

    named = re.search(r"--suite\s+(\S+)", text)
    suite = find_suite(named.group(1)) if named else None
    if suite is None:
        return False
    try:
        suite()
    except ExperimentError:
        return True
    return False


def _has_module(name: str) -> bool:
    return importlib.util.find_spec(name) is not None


def run_document(document: Path, tmp_path: Path) -> Tuple[List[str], List[str], List[Tuple[float, str]]]:
    """Run one document's commands in order in a fresh folder: (failures, not
    run, (seconds, command) of each command run)."""
    commands = collect(document)
    work = tmp_path / "work"
    (tmp_path / "home").mkdir()
    work.mkdir()
    has_shared = SHARED.is_dir()
    if has_shared:
        (tmp_path / "shared").symlink_to(SHARED)
    env = _navlab_env(tmp_path)
    failures, skipped, seconds = [], [], []
    for cmd in commands:
        if cmd.action == "skip":
            if not cmd.argument:
                failures.append(f"{cmd}: a skipped command must say why")
            skipped.append(f"{cmd} ({cmd.argument})")
            continue
        if not has_shared and ("../shared" in cmd.text or _suite_on_missing_data(cmd.text)):
            skipped.append(f"{cmd} (no ../shared beside the repository)")
            continue
        if cmd.action in ("ros", "ros-script", "serve") and not _has_module("rclpy"):
            skipped.append(f"{cmd} (the ros2 extra is not installed)")
            continue
        module = _needed_module(cmd) if cmd.action == "needs" else ""
        if cmd.action == "needs" and not (module and _has_module(module)):
            skipped.append(f"{cmd} (needs {module or 'a module the rule does not name'}, an optional extra)")
            continue
        expected = int(cmd.argument) if cmd.action == "exit" else 0
        t0 = time.perf_counter()
        try:
            done = _run(cmd, work, env)
        except subprocess.TimeoutExpired:
            failures.append(f"{cmd}\n    did not finish in {TIMEOUT_S} s")
            continue
        finally:
            seconds.append((time.perf_counter() - t0, str(cmd)))
        tail = (done.stderr.strip() or done.stdout.strip()).splitlines()[-6:]
        if done.returncode != expected:
            failures.append(f"{cmd}\n    exit {done.returncode}, the text promises {expected}\n    "
                            + "\n    ".join(tail))
        elif "Traceback (most recent call last)" in done.stderr and cmd.lang != "python":
            failures.append(f"{cmd}\n    printed a traceback\n    " + "\n    ".join(tail))
    return failures, skipped, seconds


@pytest.fixture(scope="module")
def all_documents(tmp_path_factory) -> Dict[str, Any]:
    """Every document's run, started at once: the documents are independent
    (a folder each), and most of their time is simulated robots and ROS nodes
    waiting on their clocks, so they share the machine well."""
    outcomes: Dict[str, Any] = {}
    folders = {d.name: tmp_path_factory.mktemp(d.stem) for d in DOCUMENTS}  # made here: mktemp is not thread-safe

    def one(document: Path) -> None:
        try:
            outcomes[document.name] = run_document(document, folders[document.name])
        except BaseException as exc:  # reported by the document's own test
            outcomes[document.name] = exc

    threads = [threading.Thread(target=one, args=(d,), daemon=True) for d in DOCUMENTS]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return outcomes


# The first document's test also runs every document (the fixture): ~90 commands
# on a machine the other test files share, so it gets more than the suite's 300 s.
@pytest.mark.timeout(1200)
@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda p: p.name)
def test_documented_commands_run_as_written(document: Path, all_documents) -> None:
    if not collect(document):
        pytest.skip(f"{document.name} shows no commands")
    outcome = all_documents[document.name]
    if isinstance(outcome, BaseException):
        raise outcome
    failures, skipped, seconds = outcome
    if skipped:
        print("not run:\n  " + "\n  ".join(skipped))
    # where the suite's time goes (shown with -s or -rP; the documents run at once, so these overlap)
    slowest = sorted(seconds, reverse=True)[:5]
    print(f"{document.name}: {sum(s for s, _ in seconds):.0f} s in {len(seconds)} commands; slowest:\n  "
          + "\n  ".join(f"{s:5.1f} s  {c}" for s, c in slowest))
    assert not failures, "\n".join(failures)


def test_the_directives_are_read() -> None:
    """The collector sees the blocks and the rules (a collector that found
    nothing would pass every document)."""
    commands = [c for d in DOCUMENTS for c in collect(d)]
    assert len(commands) > 40
    assert any(c.action == "add" for c in commands)
    assert any(c.action == "exit" and c.argument == "1" for c in commands)
    quick_start = [c for c in commands if c.document == "README.md" and "pip install" in c.text]
    assert quick_start and all(c.action == "skip" for c in quick_start)
    # a command runs as written unless a rule names it: spot-check one plain command
    assert any(c.action == "needs" and _added_flags(c) for c in commands)  # (the OMPL study, reduced)
    listed = [c for c in commands if c.text == "navlab list"]
    assert listed and listed[0].action == "run"


def test_split_shell_joins_continuations_and_drops_comments() -> None:
    block = "navlab a --x 1 \\\n    --y 2   # note\n# only a comment\n\nnavlab b '#not a comment'\n"
    assert _split_shell(block, 10) == [(10, "navlab a --x 1      --y 2"), (14, "navlab b '#not a comment'")]
