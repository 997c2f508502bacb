"""``sim``, the Gazebo stand-in: navlab's simulated robot in a map or world
file, driven by ``/cmd_vel``; publishes ``/odom`` (encoder odometry),
``/scan``, ``/clock``, ``/ground_truth`` (the true pose) and, with
``tf2_msgs`` installed, the ``odom → base_link`` transform on ``/tf``.

The odometry frame starts at the robot's true start pose in the map frame,
so ``map → odom`` is the identity; the node publishes it once on
``/tf_static`` so that RViz can show the scan and the robot on the map.
Steps run on a wall-clock timer at ``real_time_factor`` times real time; the
other nodes follow ``/clock`` with ``use_sim_time`` so that a run can go
faster than real time.

Obstacles with a ``motion`` (world files) move with simulated time: the
scans see them where they are, and a robot they run into stops there (the
log says who hit whom).

``scan_latency`` / ``odom_latency`` (with optional seeded jitter) hold each
``/scan`` / ``/odom`` message back that many simulated seconds while its
stamp stays the time it was measured, as seed 004 measured on its robot
(``navlab ros delay /scan /odom`` measures it back).
"""

from __future__ import annotations

import heapq
import math

import numpy as np
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan

from ..errors import ParameterError
from ..grid.occupancy import OccupancyGrid
from ..robots import Compass, WheelEncoders, make_robot
from ..sensors import Lidar
from ..sim.plant import Plant
from ..sim.scene import Scene, load_scene_world
from ..sim.simulation import MAX_DT, MIN_DT
from .base import DEFAULT_QOS, MAP_QOS, SCAN_QOS, STREAM_QOS, NavlabNode, Param, node_main
from .convert import odometry_msg, scan_to_msg, tf_message_type, time_msg, transform_msg, twist_from_msg


class SimNode(NavlabNode):
    PARAMETERS = (
        Param("world", "", "map_server YAML, Moving AI .map, world YAML or built-in scene name"),
        Param("robot", "diff", "diff (TurtleBot3 Burger), omni3 (seed 004's three-wheel omni), jackal (BARN's "
                               "0.42 × 0.33 m rectangle; its footprint is what collides) or car (a kinematic "
                               "bicycle: /cmd_vel's turn rate is bounded by its speed over its turning radius)"),
        Param("costmap_inflation_radius", 0.0, "publish the world's Nav2-style costmap for the robot's footprint "
                                               "on /costmap with this inflation radius (m; 0: none)", low=0.0),
        Param("costmap_cost_scaling_factor", 3.0, "the costmap's cost_scaling_factor (1/m)", low=0.0),
        Param("x", math.nan, "start x (m); default: the world's start (maps have none)"),
        Param("y", math.nan, "start y (m)"),
        Param("yaw", 0.0, "start heading (rad)"),
        Param("dt", 0.02, "simulation step (s); /odom is published every step"),
        Param("real_time_factor", 1.0, "simulated seconds per wall-clock second"),
        Param("scan_rate", 10.0, "LiDAR scans per simulated second (0: no /scan)", low=0.0),
        Param("lidar_beams", 360, "readings per scan", low=1),
        Param("lidar_range_max", 12.0, "LiDAR range (m)", low=0.0),
        Param("noisy", False, "seed 004 noise: RPLiDAR A1 ranges, 2% wheel speed noise, 1% slip, 1° compass"),
        Param("cmd_vel_timeout", 0.5, "stop when /cmd_vel is older than this (simulated s; 0: never)", low=0.0),
        Param("seed", 0, "random seed of the noise"),
        Param("publish_clock", True, "publish /clock (the other nodes then use use_sim_time)"),
        Param("odom_frame", "odom", "frame of /odom"),
        Param("base_frame", "base_link", "the robot's frame (/odom child, /scan frame)"),
        Param("static_map_odom", True, "publish the identity map → odom transform on /tf_static "
                                       "(turn off when a localiser publishes map → odom)"),
        Param("scan_latency", 0.0, "delay of /scan (simulated s): a scan is published this long after it is "
                                   "taken, stamped when taken (seed 004 measured 0.5 s)", low=0.0),
        Param("scan_jitter", 0.0, "standard deviation of the /scan delay (s), seeded", low=0.0),
        Param("odom_latency", 0.0, "delay of /odom (simulated s; seed 004 measured 0.08 s)", low=0.0),
        Param("odom_jitter", 0.0, "standard deviation of the /odom delay (s), seeded", low=0.0),
        Param("odom_rate", 0.0, "/odom messages per simulated second (0: every step)", low=0.0),
    )

    def __init__(self, **kwargs) -> None:
        super().__init__("sim", **kwargs)
        p = self.params
        if not p["world"]:
            raise ParameterError("sim needs a world: -p world:=maze.yaml (a map, world file or scene name)")
        for name in ("dt", "real_time_factor"):
            if not (p[name] > 0 and math.isfinite(p[name])):
                raise ParameterError(f"{name} must be positive, got {p[name]!r}")
        if p["dt"] < MIN_DT:
            raise ParameterError(f"dt = {p['dt']:g} s is below the smallest supported step, {MIN_DT:g} s")
        if p["dt"] > MAX_DT:
            raise ParameterError(f"dt = {p['dt']:g} s is above the largest supported step, {MAX_DT:g} s")
        world = load_scene_world(p["world"])
        self.robot = make_robot(p["robot"])
        start = (p["x"], p["y"], p["yaw"])
        if math.isnan(p["x"]) != math.isnan(p["y"]):  # (a lone x:=2 was dropped without a word)
            raise ParameterError("set the start's x and y together: -p x:=... -p y:=...")
        if math.isnan(p["x"]):
            if isinstance(world, OccupancyGrid):
                raise ParameterError("a map has no start of its own: set -p x:=... -p y:=... to finite numbers "
                                     "(NaN, the default, means the world's own start)")
            start = (*world.start, p["yaw"])
        self.scene = Scene(world, self.robot.radius, self.robot.footprint)
        if not self.scene.free(start):
            raise ParameterError(f"the robot cannot start there: {self.scene.describe(start)}")
        noisy = p["noisy"]
        self.plant = Plant(self.scene, self.robot, start,
                           WheelEncoders(noise=0.02 if noisy else 0.0, slip=0.01 if noisy else 0.0),
                           Compass(noise_deg=1.0) if noisy else None)
        self.lidar = Lidar(beams=p["lidar_beams"], range_max=p["lidar_range_max"],
                           noise="rplidar_a1" if noisy else None)
        self.rng = np.random.default_rng(p["seed"])
        self.dt = p["dt"]
        for name in ("scan_latency", "scan_jitter", "odom_latency", "odom_jitter", "odom_rate"):
            if not (p[name] >= 0 and math.isfinite(p[name])):
                raise ParameterError(f"{name} must be a number ≥ 0, got {p[name]!r}")
        # delays have their own generator: a run without them draws exactly as before
        self.delay_rng = np.random.default_rng(np.random.SeedSequence(int(p["seed"]), spawn_key=(4,)))
        self.odom_every = max(1, round(1.0 / (p["odom_rate"] * self.dt))) if p["odom_rate"] > 0 else 1
        self.outbox: list = []  # (publish at [s], sequence, publisher, message): delayed messages in flight
        self.sent = 0
        self.scan_every = max(1, round(1.0 / (p["scan_rate"] * self.dt))) if p["scan_rate"] > 0 else 0
        self.steps, self.t = 0, 0.0
        self.command, self.command_t = (0.0, 0.0, 0.0), -math.inf
        self.in_contact = False
        self.odom_pub = self.create_publisher(Odometry, "odom", STREAM_QOS)
        self.truth_pub = self.create_publisher(Odometry, "ground_truth", STREAM_QOS)
        self.scan_pub = self.create_publisher(LaserScan, "scan", SCAN_QOS) if self.scan_every else None
        self.clock_pub = self.create_publisher(Clock, "clock", STREAM_QOS) if p["publish_clock"] else None
        self.tf_type = tf_message_type()
        self.tf_pub = self.create_publisher(self.tf_type, "tf", STREAM_QOS) if self.tf_type else None
        if self.tf_pub is None:
            from ..extras import install_command

            self.log("warn", f"tf2_msgs is not installed ({install_command('ros2')} builds it): "
                             "odom → base_link is not published on /tf; /odom carries the same pose")
        elif p["static_map_odom"]:
            self.tf_static_pub = self.create_publisher(self.tf_type, "tf_static", MAP_QOS)
            self.tf_static_pub.publish(self.tf_type(transforms=[
                transform_msg((0.0, 0.0, 0.0), "map", p["odom_frame"], time_msg(self.t))]))
        if p["costmap_inflation_radius"] > 0:
            from nav_msgs.msg import OccupancyGrid as GridMsg

            from ..world.costmap import build_costmap
            from .convert import costmap_to_msg

            costmap = build_costmap(world, self.robot.shape, p["costmap_inflation_radius"],
                                    p["costmap_cost_scaling_factor"])
            self.costmap_pub = self.create_publisher(GridMsg, "costmap", MAP_QOS)
            self.costmap_pub.publish(costmap_to_msg(costmap, "map", time_msg(self.t)))
        self.create_subscription(Twist, "cmd_vel", self.on_cmd_vel, DEFAULT_QOS)
        self.publish_state()
        self.steady_timer(self.dt / p["real_time_factor"], self.step)
        self.log("info", f"{p['robot']} robot in {p['world']} at ({start[0]:g}, {start[1]:g}, {start[2]:g}), "
                         f"step {self.dt:g} s, {p['real_time_factor']:g}x real time")

    def on_cmd_vel(self, msg) -> None:
        try:
            self.command = twist_from_msg(msg)
        except ValueError as exc:
            self.log("error", f"ignoring /cmd_vel: {exc}")
            return
        self.command_t = self.t

    def step(self) -> None:
        timeout = self.params["cmd_vel_timeout"]
        stale = timeout > 0 and self.t - self.command_t > timeout
        vx, vy, omega = (0.0, 0.0, 0.0) if stale else self.command
        before = self.plant.pose.copy()
        if self.plant.step(vx, vy, omega, self.dt, self.rng, self.t):
            # the robot pushes against the obstacle and stays put; the wheels turn
            self.plant.pose = before
            if not self.in_contact:
                self.log("error", self.plant.hit)
            self.in_contact = True
        else:
            self.in_contact = False
        self.steps += 1
        self.t = self.steps * self.dt
        self.publish_state()

    def publish_state(self) -> None:
        stamp = time_msg(self.t)
        if self.clock_pub is not None:
            self.clock_pub.publish(Clock(clock=stamp))
        p = self.params
        twist = self.plant.last_twist
        odom = self.plant.odometry.pose
        if self.steps % self.odom_every == 0:
            self.send(self.odom_pub, odometry_msg(odom, twist, p["odom_frame"], p["base_frame"], stamp),
                      p["odom_latency"], p["odom_jitter"])
        self.truth_pub.publish(odometry_msg(self.plant.pose, twist, "map", p["base_frame"], stamp))
        if self.scan_pub is not None and self.steps % self.scan_every == 0:
            self.scene.set_time(self.t)  # moving obstacles where they are now
            ranges = self.lidar.scan(self.scene, self.plant.pose, self.rng)
            self.send(self.scan_pub, scan_to_msg(ranges, self.lidar, p["base_frame"], stamp,
                                                 scan_time=self.scan_every * self.dt),
                      p["scan_latency"], p["scan_jitter"])
        self.flush()
        if self.tf_pub is not None:
            self.tf_pub.publish(self.tf_type(transforms=[transform_msg(odom, p["odom_frame"], p["base_frame"], stamp)]))


    def send(self, publisher, msg, latency: float, jitter: float) -> None:
        """Publish now, or ``latency`` (± jitter) simulated seconds later with
        the stamp of when it was measured."""
        if latency == 0 and jitter == 0:
            publisher.publish(msg)
            return
        delay = max(0.0, latency + (jitter * float(self.delay_rng.standard_normal()) if jitter else 0.0))
        self.sent += 1
        heapq.heappush(self.outbox, (self.t + delay, self.sent, publisher, msg))

    def flush(self) -> None:
        """Publish the delayed messages that are due (a step's slack of 1e-9 s)."""
        while self.outbox and self.outbox[0][0] <= self.t + 1e-9:
            _, _, publisher, msg = heapq.heappop(self.outbox)
            publisher.publish(msg)


main = node_main(SimNode)

if __name__ == "__main__":
    main()
