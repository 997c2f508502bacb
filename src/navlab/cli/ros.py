"""``navlab ros``: the ROS 2 nodes, a one-command demo and bag recording
(the ``ros2`` extra)."""

from __future__ import annotations

import json
import math
import sys

import click

from ..ros.launch import NODES
from .common import (EXIT_INTERRUPTED, Count, FiniteNumber, NonNegativeNumber, PositiveNumber, SuggestingChoice,
                     SuggestingGroup, parse_params)


def ros_hint() -> str:
    """What a ros verb says without the ros2 extra (:func:`navlab.extras.install_command`)."""
    from ..extras import install_command

    return f"ROS 2 is not installed: {install_command('ros2')}"


def _require_rclpy() -> None:
    try:
        import rclpy  # noqa: F401
    except ImportError as exc:
        error = click.ClickException(f"{ros_hint()} ({exc})")
        error.exit_code = 2  # a setting that cannot work, as every input error
        raise error from None


@click.group("ros", cls=SuggestingGroup)
def ros_group() -> None:
    """ROS 2 nodes: map_server, sim, pathplanner (alias astar_pathplanner), goto_waypoint,
    potential_field_navigator, local_planner (dwa, mppi, rpp on a costmap); `navlab ros demo` runs a
    whole pipeline.

    Run a node with ROS arguments, e.g.

      navlab ros map_server --ros-args -p yaml_filename:=maze.yaml

    Each node is also a console script (navlab-map-server, navlab-sim, ...).
    `navlab ros NODE --help` lists its parameters.
    """


class NodeCommand(click.Command):
    """A node as a subcommand: everything after the name goes to ROS; the
    help lists the node's parameters (which needs rclpy)."""

    def __init__(self, node: str) -> None:
        super().__init__(node, callback=self.run, add_help_option=True,
                         context_settings={"ignore_unknown_options": True, "allow_extra_args": True,
                                           "help_option_names": ["-h", "--help"]},
                         help=f"Run the {node} node (ROS arguments follow: --ros-args -p NAME:=VALUE).",
                         short_help=f"Run the {node} node.")
        self.node = node

    def format_help_text(self, ctx, formatter) -> None:
        super().format_help_text(ctx, formatter)
        try:
            from ..ros.base import parameter_help
            from ..ros.launch import node_class

            cls = node_class(self.node)
            text = (sys.modules[cls.__module__].__doc__ or "").strip().replace("``", "")
            with formatter.indentation():
                for paragraph in text.split("\n\n"):
                    formatter.write_paragraph()
                    formatter.write_text(" ".join(paragraph.split()))
            formatter.write_paragraph()
            formatter.write_text("Parameters (--ros-args -p NAME:=VALUE):")
            formatter.write(parameter_help(cls.PARAMETERS) + "\n")
        except ImportError:
            formatter.write_paragraph()
            formatter.write_text(ros_hint())

    def run(self) -> None:
        _require_rclpy()
        from ..ros.base import run_node
        from ..ros.launch import node_class

        ctx = click.get_current_context()
        before = ctx.args[:ctx.args.index("--ros-args")] if "--ros-args" in ctx.args else ctx.args
        if "-p" in before or "--param" in before:  # rclpy reads -p only after --ros-args: it was ignored
            raise click.UsageError(f"ROS parameters follow --ros-args: navlab ros {self.node} --ros-args "
                                   "-p NAME:=VALUE ...")
        sys.exit(run_node(node_class(self.node), [f"navlab-{self.node}", *ctx.args]))


def _strict_json(value):
    """``value`` with every NaN or infinite float as None: JSON has neither (Python writes the
    non-standard ``NaN`` and ``Infinity``, which strict parsers refuse: a run that heard no
    odometry, a topic that sent nothing)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _strict_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_strict_json(v) for v in value]
    return value


for _node in NODES:
    ros_group.add_command(NodeCommand(_node))


@ros_group.command("delay", short_help="Measure how late messages arrive on topics.")
@click.argument("topics", nargs=-1, required=True)
@click.option("--duration", type=PositiveNumber(), default=10.0, show_default=True,
              help="How long to listen (wall-clock seconds, from when the first topic appears).")
@click.option("--wait", type=NonNegativeNumber(), default=10.0, show_default=True,
              help="How long to wait for the topics to appear (wall-clock seconds).")
@click.option("--time", "clock", type=SuggestingChoice(["auto", "sim", "wall"]), default="auto", show_default=True,
              help="Receive time from /clock (sim) or the system clock (wall); auto: sim when /clock is published.")
@click.option("--json", "as_json", is_flag=True, help="One JSON object per topic.")
def delay_cmd(topics, duration, wait, clock, as_json) -> None:
    """Measure how late messages arrive on TOPICS: receive time minus
    header.stamp per message, and the rate, as mean / min / max / count per
    topic (seed 004's Tables 3–4). Works on any ROS 2 graph.

    \b
    Example (with `navlab ros sim` running):
      navlab ros delay /scan /odom --duration 10
    """
    _require_rclpy()
    from ..ros.delay import measure, table

    summaries, used = measure(list(topics), duration, clock, wait=wait, args=["navlab-delay"])
    if as_json:
        for s in summaries:
            click.echo(json.dumps(_strict_json(s | {"clock": used})))
    else:
        click.echo(table(summaries, used))
    if any(s["count"] == 0 for s in summaries):
        sys.exit(1)


@ros_group.command("demo", short_help="Drive a simulated robot to a goal through ROS 2 nodes.")
@click.option("--map", "--world", "world", default=None,
              help="map_server YAML (diff drive) or world file / scene (omni3). Default: a generated maze for "
                   "diff, the one_obstacle scene for omni3.")
@click.option("--robot", type=SuggestingChoice(["diff", "omni3"]), default="diff", show_default=True,
              help="diff: map_server + sim + pathplanner + goto_waypoint; omni3: sim + "
                   "potential_field_navigator.")
@click.option("--start", nargs=2, type=FiniteNumber(), default=None, metavar="X Y", help="Start (m); maps need one.")
@click.option("--yaw", type=FiniteNumber(), default=0.0, show_default=True, help="Start heading (rad).")
@click.option("--goal", nargs=2, type=FiniteNumber(), default=None, metavar="X Y", help="Goal (m); maps need one.")
@click.option("--maze-size", type=Count(low=2), default=8, show_default=True,
              help="Cells per side of the generated maze (when no --map is given).")
@click.option("--real-time-factor", "--rtf", type=PositiveNumber(), default=5.0,
              show_default=True, help="Simulated seconds per wall-clock second.")
@click.option("--processes", is_flag=True, help="Run each node in its own process (as a real system does).")
@click.option("--record", type=click.Path(file_okay=False), default=None,
              help="Record every topic to this new rosbag2 (MCAP) directory.")
@click.option("--max-time", type=PositiveNumber(), default=600.0, show_default=True,
              help="Simulated-time budget after the goal is sent (s).")
@click.option("--timeout", type=PositiveNumber(), default=300.0, show_default=True,
              help="Wall-clock limit (s).")
@click.option("--log-dir", type=click.Path(file_okay=False), default=None,
              help="With --processes: one log file per node here.")
@click.option("--planner", default="astar", show_default=True, help="diff: the pathplanner's algorithm (any planner).")
@click.option("--param", "params", multiple=True, metavar="KEY=VALUE",
              help="diff: a pathplanner parameter (sampler=integration, seed=3, max_iter=3000, ...); repeatable.")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON.")
def demo_cmd(world, robot, start, yaw, goal, maze_size, real_time_factor, processes, record, max_time, timeout,
             log_dir, planner, params, as_json) -> None:
    """Drive a simulated robot to a goal through the ROS 2 nodes, in one
    command, and judge the run from /odom.

    Exit status 0 when the robot stopped within 0.1 m of the goal, 130 after
    Ctrl-C, 1 otherwise.
    """
    _require_rclpy()
    from ..ros.demo import run_demo

    summary = run_demo(world, robot, None if start is None else (*start, yaw), goal, maze_size=maze_size,
                       real_time_factor=real_time_factor, processes=processes, record=record,
                       max_time=max_time, timeout=timeout, log_dir=log_dir, planner=planner,
                       planner_params=parse_params(params))
    if as_json:
        click.echo(json.dumps(_strict_json(summary)))
    else:
        click.echo(f"{summary['status']}" + (f": {summary['reason']}" if summary["reason"] else ""))
        odom, true = (summary[key] for key in ("error_odom_m", "error_true_m"))
        # (at 4 decimals: a 5-cell maze's goal printed as [2.7499999999999996, 2.7499999999999996])
        goal = "[" + ", ".join(f"{round(float(v), 4):g}" for v in summary["goal"]) + "]"
        if math.isfinite(odom) and math.isfinite(true):
            click.echo(f"  goal {goal}, odometry {odom * 1000:.0f} mm and true pose {true * 1000:.0f} mm "
                       "from it")
        else:  # (it printed "inf mm" when the run ended before the robot was heard)
            click.echo(f"  goal {goal}; the robot's pose was never heard")
        click.echo(f"  {summary['sim_time_s']:.1f} s simulated in {summary['wall_time_s']:.1f} s, "
                   f"travelled {summary['travelled_m']:.2f} m"
                   + (f", plan {summary['plan_length_m']:.2f} m" if summary["plan_length_m"] else ""))
        for line in summary["warnings"]:
            click.echo(f"  {line}")
        if "recorded" in summary:
            counts = summary["recorded"]["messages"]
            listed = ", ".join(f"{topic} {n}" for topic, n in counts.items()) if isinstance(counts, dict) else counts
            click.echo(f"  recorded to {summary['recorded']['path']}: messages per topic: {listed}")
    sys.exit({"REACHED": 0, "INTERRUPTED": EXIT_INTERRUPTED}.get(summary["status"], 1))
