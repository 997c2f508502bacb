"""What every navlab ROS 2 node shares: declared parameters with their help,
quality-of-service profiles, logging into the decision cores, and a main
that turns bad settings into one error line."""

from __future__ import annotations

import math
import re
import signal
import sys
import time
from typing import Any, Callable, Dict, List, NamedTuple, Optional, Sequence

import rclpy
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.clock import Clock, ClockType
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data

from ..errors import ParameterError
from ..registry import UnknownNameError, suggest
from .convert import stamp_seconds

#: /map is latched: late subscribers get the last map (as nav2's map_server).
MAP_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE)
#: /plan is latched too: a follower whose process starts (or is discovered)
#: after the planner answered the goal still gets the path; without it the
#: robot never moves (a CI run lost the only plan this way).
PLAN_QOS = MAP_QOS
#: /scan as drivers publish it (best effort, keep the latest few).
SCAN_QOS = qos_profile_sensor_data
#: /odom, /cmd_vel, /goal_pose
DEFAULT_QOS = 10
#: the sim's 50 Hz streams (/odom, /ground_truth, /tf, /clock) on the writer
#: side: a reliable reader that falls behind for a moment (a bag recorder
#: sharing the CPU with a sim at 10x real time) gets the missed samples
#: resent from this history instead of losing them.
STREAM_QOS = 200


class Param(NamedTuple):
    """A ROS parameter of a navlab node: name, default (its type fixes the
    parameter's type) and a one-line description."""

    name: str
    default: Any
    description: str
    #: the smallest value a number may take (rates, delays, timeouts: 0), or None
    low: Any = None


def parameter_help(params: Sequence[Param]) -> str:
    return "\n".join(f"  {p.name} (default {p.default!r}): {p.description}" for p in params)


def coerce(param: Param, value: Any) -> Any:
    """``value`` as the type of the parameter's default (ints widen to
    floats); anything else is refused with the parameter's name."""
    kind = type(param.default)
    if kind is float and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
        raise ParameterError(f"parameter {param.name} must be {kind.__name__}, got {value!r}")
    if kind is float and not math.isfinite(value) and math.isfinite(param.default):
        raise ParameterError(f"parameter {param.name} must be a finite number, got {value!r}")
    if param.low is not None and value < param.low:
        raise ParameterError(f"parameter {param.name} must be at least {param.low:g}, got {value!r}")
    if param.name == "seed" and value < 0:  # numpy's generators take non-negative seeds only
        raise ParameterError(f"parameter seed must be a non-negative integer, got {value!r}")
    return value


def command_line_parameters(argv: Sequence[str]) -> set:
    """The names ``argv`` sets with ``-p NAME:=VALUE`` (or ``--param``, or ``-p NODE:NAME:=VALUE``) inside
    its ``--ros-args`` sections, where ROS reads them."""
    names, inside, expect = set(), False, False
    for token in argv:
        if token == "--ros-args":
            inside = True
        elif token == "--":
            inside = False
        elif inside and expect:
            names.add(token.split(":=", 1)[0].rsplit(":", 1)[-1])
            expect = False
        elif inside and token in ("-p", "--param"):
            expect = True
    return names


#: parameters every rclpy node has, or that configure ROS itself: never a planner's or controller's setting
ROS_OWN = frozenset({"use_sim_time", "start_type_description_service"})


class NavlabNode(Node):
    """A node with declared parameters (``self.params``) and a ``log(level,
    text)`` for the decision cores."""

    PARAMETERS: Sequence[Param] = ()

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name, **kwargs)
        if not kwargs.get("automatically_declare_parameters_from_overrides"):
            # (a node that declares every override hands the others on to its planner or controller, which
            # checks them: passed_settings)
            self._refuse_unknown_parameters()
        self.params: Dict[str, Any] = {}
        for p in self.PARAMETERS:
            # dynamic typing, then our own check: `-p x:=1` for a float must work
            if not self.has_parameter(p.name):  # a node that declares every override has it already
                self.declare_parameter(p.name, p.default, ParameterDescriptor(description=p.description,
                                                                             dynamic_typing=True))
            self.params[p.name] = coerce(p, self.get_parameter(p.name).value)

    def _refuse_unknown_parameters(self) -> None:
        """Refuse a ``-p NAME:=VALUE`` on the command line that names none of the node's parameters: rclpy
        drops such a value unread, so a typo (``-p real_time_factr:=10``) ran on the default without a word,
        where the path planner nodes already refused it. One from a params file is a warning: a file's
        ``/**`` section, shared by several nodes, names parameters of the others (review, session 20)."""
        overrides = getattr(self, "_parameter_overrides", None) or {}  # rclpy's -p values (no public getter)
        own = [p.name for p in self.PARAMETERS]
        typed = command_line_parameters(sys.argv)
        for name in overrides:
            if name in own or name in ROS_OWN or name.startswith("qos_overrides."):
                continue
            message = (f"unknown parameter '{name}' for the {self.get_name()} node; its parameters: "
                       f"{', '.join(own) or 'none'}." + suggest(name, own))
            if name in typed:
                raise ParameterError(message)
            self.log("warn", f"{message} Ignored (from a params file).")

    def passed_settings(self, convert: Optional[Callable[[str, Any], Any]] = None) -> Dict[str, Any]:
        """The ``-p NAME:=VALUE`` parameters that are neither the node's own nor ROS's
        (``use_sim_time``, QoS overrides, ...): the settings a node hands on to the
        planner or controller it runs, each passed through ``convert(name, value)``
        when given; arrays as lists."""
        own = {q.name for q in self.PARAMETERS} | ROS_OWN
        out = {}
        for name, param in self.get_parameters_by_prefix("").items():
            if name in own or name.startswith("qos_overrides."):
                continue
            value = param.value if convert is None else convert(name, param.value)
            out[name] = list(value) if isinstance(value, (list, tuple)) or hasattr(value, "tolist") else value
        return out

    def read(self, convert: Callable[[Any], Any], msg: Any, topic: str) -> Any:
        """``convert(msg)``, or None with one error line naming the topic when the message is malformed."""
        try:
            return convert(msg)
        except (ValueError, TypeError) as exc:
            self.log("error", f"ignoring a malformed {topic}: {exc}")
            return None

    def log(self, level: str, text: str) -> None:
        # one call site per severity: rclpy refuses a call site whose severity changes
        logger = self.get_logger()
        if level == "error":
            logger.error(text)
        elif level == "warn":
            logger.warning(text)
        else:
            logger.info(text)

    def steady_timer(self, period: float, callback: Callable[[], None]):
        """A timer on the monotonic clock: it keeps firing when simulated
        time stops (that is when watchdogs matter)."""
        return self.create_timer(period, callback, clock=Clock(clock_type=ClockType.STEADY_TIME))

    @staticmethod
    def monotonic() -> float:
        return time.monotonic()

    def stamp_seconds(self, stamp) -> float:
        """A header stamp in seconds; the node's clock when the stamp is zero."""
        t = stamp_seconds(stamp)
        return t if t > 0 else self.get_clock().now().nanoseconds * 1e-9


def _executor():
    """rclpy's SingleThreadedExecutor, built with SIGINT and SIGTERM held back in this thread; None
    when a signal has already shut ROS down (the demo stopped as its nodes start: building one on a
    shut-down context raises, and the half-built executor's ``__del__`` printed a traceback)."""
    from rclpy.executors import SingleThreadedExecutor

    class Executor(SingleThreadedExecutor):
        def __del__(self) -> None:
            if hasattr(self, "_sigint_gc"):  # only a whole one has anything to release
                super().__del__()

    held = {signal.SIGINT, signal.SIGTERM}
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        return Executor()
    except Exception:
        if rclpy.ok():
            raise
        return None  # a signal (delivered to another thread) shut ROS down first
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _own_parameters_hint(factory: Callable[[], Node], exc: Exception) -> str:
    """For an unknown setting handed on to a planner or controller, the node's
    own parameters too: the planner's list of valid names leaves them out, and
    a misspelt node parameter (``inflaton_radius``) lands there."""
    match = re.match(r"unknown parameter '([^']*)'", str(exc))
    own = [p.name for p in getattr(factory, "PARAMETERS", ())]
    if not isinstance(exc, UnknownNameError) or match is None or not own:
        return ""
    return f" The node's own parameters: {', '.join(own)}.{suggest(match.group(1), own)}"


def run_node(factory: Callable[[], Node], args: Optional[List[str]] = None) -> int:
    """Initialise ROS, build the node and spin until Ctrl-C or shutdown.

    Returns the process exit status: 2 when the node refuses its settings
    (the reason printed on one line), 0 otherwise.
    """
    try:
        rclpy.init(args=args)
    except RuntimeError as exc:  # rcl's RCLError: ROS arguments it cannot parse (`-p x:={a: 1}`)
        print(f"Error: bad ROS arguments: {exc}", file=sys.stderr)
        return 2
    try:
        try:
            node = factory()
        except (ValueError, FileNotFoundError, KeyError) as exc:
            print(f"Error: {exc}{_own_parameters_hint(factory, exc)}", file=sys.stderr)
            return 2
        except Exception:
            if rclpy.ok():
                raise
            return 0  # Ctrl-C while the node was being built: rclpy has shut down under it
        executor = _executor()
        try:
            if executor is None:
                return 0
            executor.add_node(node)
            executor.spin()
        except (KeyboardInterrupt, ExternalShutdownException):
            pass
        except Exception:
            if rclpy.ok():
                raise
            # SIGINT/SIGTERM shut rclpy down while a callback was publishing
        finally:
            # a second Ctrl-C must not break the teardown with a traceback
            signal.signal(signal.SIGINT, signal.SIG_IGN)
            node.destroy_node()
    finally:
        rclpy.try_shutdown()
    return 0


def node_main(factory: Callable[[], Node]) -> Callable[[Optional[List[str]]], None]:
    """A console-script entry point for a node class."""

    def main(args: Optional[List[str]] = None) -> None:
        sys.exit(run_node(factory, args if args is not None else sys.argv))

    return main
