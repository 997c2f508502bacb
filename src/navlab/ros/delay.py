"""``navlab ros delay``: how late messages arrive, measured as seed 004 did.

For every message on each topic: the delay is the receive time minus the
message's ``header.stamp``, and the inter-arrival times give the rate; the
summary is mean / min / max / count per topic (the seed's Tables 3–4). Any
ROS 2 graph will do: a topic's type is looked up in the graph and its
message class imported by name. The receive time is the node's clock: ROS
time following ``/clock`` when the graph publishes one (simulated time), the
system clock otherwise (``--time`` forces either).

Topics whose messages have no ``header.stamp`` get one line saying so and
still get their rate.
"""

from __future__ import annotations

import importlib
import math
import time
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence
from ..errors import ParameterError


@dataclass
class TopicDelay:
    """Delays and arrival times of one topic (seconds)."""

    topic: str
    type_name: str = ""
    has_stamp: Optional[bool] = None
    delays: List[float] = field(default_factory=list)
    arrivals: List[float] = field(default_factory=list)

    def add(self, receive_t: float, stamp_t: Optional[float]) -> None:
        self.arrivals.append(receive_t)
        if stamp_t is not None:
            self.delays.append(receive_t - stamp_t)

    def summary(self) -> Dict[str, Any]:
        d, a = self.delays, self.arrivals
        rate = (len(a) - 1) / (a[-1] - a[0]) if len(a) > 1 and a[-1] > a[0] else math.nan
        out: Dict[str, Any] = {"topic": self.topic, "type": self.type_name, "count": len(a), "rate_hz": rate,
                               "has_stamp": self.has_stamp}
        if d:
            out |= {"delay_mean_s": sum(d) / len(d), "delay_min_s": min(d), "delay_max_s": max(d)}
        else:
            out |= {"delay_mean_s": math.nan, "delay_min_s": math.nan, "delay_max_s": math.nan}
        return out


def message_class(type_name: str):
    """The Python class of ``pkg/msg/Name`` (imported from ``pkg.msg``)."""
    package, _, name = type_name.partition("/msg/")
    if not name:
        raise ParameterError(f"not a message type: {type_name!r}")
    return getattr(importlib.import_module(f"{package}.msg"), name)


def stamp_of(msg) -> Optional[float]:
    """``header.stamp`` in seconds, or None when the message has none."""
    header = getattr(msg, "header", None)
    stamp = getattr(header, "stamp", None)
    if stamp is None or not hasattr(stamp, "sec"):
        return None
    return stamp.sec + stamp.nanosec * 1e-9


def table(summaries: Sequence[Dict[str, Any]], clock: str) -> str:
    """The seed's Tables 3–4 layout: one row per topic."""
    lines = [f"delay = receive time ({clock} clock) − header.stamp",
             f"{'topic':<24} {'count':>6} {'mean s':>8} {'min s':>8} {'max s':>8} {'rate Hz':>8}"]
    notes = []
    for s in summaries:
        def f(v):
            return f"{v:>8.3f}" if isinstance(v, float) and math.isfinite(v) else f"{'-':>8}"
        lines.append(f"{s['topic']:<24} {s['count']:>6} {f(s['delay_mean_s'])} {f(s['delay_min_s'])} "
                     f"{f(s['delay_max_s'])} {f(s['rate_hz'])}")
        if s["count"] == 0:
            notes.append(f"{s['topic']}: no message received" + (f" ({s['type']})" if s["type"]
                                                                   else " (no publisher seen)"))
        elif s["has_stamp"] is False:
            notes.append(f"{s['topic']}: {s['type']} has no header stamp: no delay, rate only")
    return "\n".join(lines + notes)


def measure(topics: Sequence[str], duration: float, clock: str = "auto", discovery: float = 0.5,
            wait: float = 10.0, args: Optional[List[str]] = None) -> tuple:
    """Subscribe to ``topics`` for ``duration`` wall-clock seconds, counted
    from when the first of them appears in the graph (waiting at most
    ``wait`` seconds for that).

    Returns (summaries, clock used: "sim" or "wall").
    """
    import rclpy
    from rclpy.node import Node
    from rclpy.parameter import Parameter
    from rclpy.qos import qos_profile_sensor_data

    if not duration > 0 or not math.isfinite(duration):
        raise ParameterError(f"--duration must be a positive number of seconds, got {duration!r}")
    if not wait >= 0 or not math.isfinite(wait):  # (NaN passed click's range check)
        raise ParameterError(f"--wait must be a number of seconds ≥ 0, got {wait!r}")
    if clock not in ("auto", "sim", "wall"):
        raise ParameterError(f"--time must be auto, sim or wall, got {clock!r}")
    topics = [t if t.startswith("/") else "/" + t for t in topics]
    from rclpy.exceptions import InvalidTopicNameException
    from rclpy.validate_topic_name import validate_topic_name

    for topic in topics:  # (a bad name waited out --wait and said "no message received")
        try:
            validate_topic_name(topic)
        except InvalidTopicNameException as exc:
            why = str(exc).splitlines()[0].removeprefix("Invalid topic name: ").rstrip(":")
            raise ParameterError(f"{topic[1:]!r} is not a topic name: {why}") from None
    rclpy.init(args=args)
    try:
        node = Node("navlab_delay")
        stats = {t: TopicDelay(t) for t in topics}
        # discovery: wait (up to ``wait`` s) for a first topic to appear, then a little longer for the rest
        give_up = time.monotonic() + wait
        graph: dict = {}
        while time.monotonic() < give_up and not any(t in graph for t in topics):
            rclpy.spin_once(node, timeout_sec=0.05)
            graph = dict(node.get_topic_names_and_types())
        settle = time.monotonic() + discovery
        while time.monotonic() < settle:
            rclpy.spin_once(node, timeout_sec=0.05)
        graph = dict(node.get_topic_names_and_types())
        end = time.monotonic() + duration
        use_sim = clock == "sim" or (clock == "auto" and "/clock" in graph)
        if use_sim:
            node.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, True)])
        subscribed = set()

        def subscribe_new(graph) -> None:
            for t in topics:
                if t in subscribed or t not in graph:
                    continue
                type_name = graph[t][0]
                stats[t].type_name = type_name
                subscribed.add(t)
                try:
                    cls = message_class(type_name)
                except (ImportError, AttributeError, ValueError):
                    stats[t].type_name = f"{type_name} (its Python message package is not installed)"
                    continue

                def callback(msg, t=t) -> None:
                    now = node.get_clock().now().nanoseconds * 1e-9
                    stamp = stamp_of(msg)
                    stats[t].has_stamp = stamp is not None
                    stats[t].add(now, stamp)

                # best effort matches every publisher (a reliable subscription would miss sensor-data ones)
                node.create_subscription(cls, t, callback, qos_profile_sensor_data)

        subscribe_new(graph)
        last_look = time.monotonic()
        while time.monotonic() < end:
            rclpy.spin_once(node, timeout_sec=0.02)
            if len(subscribed) < len(topics) and time.monotonic() - last_look > 0.5:
                subscribe_new(dict(node.get_topic_names_and_types()))
                last_look = time.monotonic()
        node.destroy_node()
    finally:
        rclpy.try_shutdown()
    return [stats[t].summary() for t in topics], ("sim" if use_sim else "wall")
