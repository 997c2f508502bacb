"""The seeds' navigation experiments, reproduced in the simulator.

- ``seed004``: the omni robot with a potential field from (0, 0) to four
  targets 3 m away, without and with an obstacle on the straight line,
  5 runs each with sensor and wheel noise.
- ``seed002``: generated 10×10 and 15×15 mazes, A* with smoothing from the
  robot's cell to the two far corners, the TurtleBot3-like differential
  drive following with goto_waypoint.
"""

from __future__ import annotations

from typing import Any, Callable, Dict, List, Optional

import numpy as np

from ..registry import Registry
from ..wording import counted
from ..world import World
from ..world.shapes import Circle, Rectangle
from ..world.world import Bounds

EXPERIMENTS: Registry[Callable[..., List[Dict[str, Any]]]] = Registry("experiment")

SEED004_TARGETS = ((0.0, 3.0), (0.0, -3.0), (3.0, 0.0), (-3.0, 0.0))
#: The obstacle: a 0.15 m cylinder half way, 2 cm off the line (a field
#: exactly symmetric about the line has a saddle the robot would sit on
#: without noise; the real obstacle was never perfectly centred either).
SEED004_OBSTACLE_RADIUS = 0.15
SEED004_OFFSET = 0.02


def seed004_world(target, obstacle: bool) -> World:
    tx, ty = target
    obstacles = ()
    if obstacle:
        nx, ny = -ty / 3.0, tx / 3.0  # unit normal to the line
        obstacles = (Circle((tx / 2 + SEED004_OFFSET * nx, ty / 2 + SEED004_OFFSET * ny), SEED004_OBSTACLE_RADIUS),)
    return World("seed004" + ("_obstacle" if obstacle else ""), Bounds(-5.0, 5.0, -5.0, 5.0), (0.0, 0.0),
                 tuple(target), obstacles)


def seed004_simulation(target, obstacle: bool, dt: float = 0.05):
    """The seed 004 set-up for one target: Omni3, RPLiDAR A1 noise, 2% wheel
    speed noise, up to 1% slip, a compass with 1° noise and 5° mounting
    offset, potential field with navlab's defaults."""
    from ..control import PotentialField
    from ..robots import Compass, Omni3, WheelEncoders
    from ..sensors import Lidar
    from .simulation import Simulation

    world = seed004_world(target, obstacle)
    return Simulation(world, Omni3(), PotentialField(), (0.0, 0.0, 0.0), target, lidar=Lidar(noise="rplidar_a1"),
                      encoders=WheelEncoders(ticks_per_rev=1440, noise=0.02, slip=0.01),
                      compass=Compass(noise_deg=1.0, offset_deg=5.0), dt=dt, max_time=60.0)


@EXPERIMENTS.register("omni-potential-field")
@EXPERIMENTS.register("seed004")
def seed004(runs: int = 5, seed: int = 0, plot_dir: Optional[str] = None, **_: Any) -> List[Dict[str, Any]]:
    """One row per run: target, obstacle, status, final true and odometry
    positions, their errors and the time: lengths in mm as the seed's tables
    give them, each such key ending ``_mm`` (``final_true`` and ``target``
    were mm here and metres in ``navlab sim --json``: newcomer, session 29)."""
    rows = []
    for target in SEED004_TARGETS:
        for obstacle in (False, True):
            sim = seed004_simulation(target, obstacle)
            for run in range(runs):
                run_seed = np.random.SeedSequence([seed, int(target[0] * 10) + 100, int(target[1] * 10) + 100,
                                                   int(obstacle), run]).generate_state(1)[0]
                result = sim.run(int(run_seed))
                rows.append({
                    "experiment": "seed004", "target_mm": [1000 * target[0], 1000 * target[1]], "obstacle": obstacle,
                    "run": run + 1, "seed": int(run_seed), "status": result.status.name,
                    "final_true_mm": (1000 * result.final_true[:2]).tolist(),
                    "final_odom_mm": (1000 * result.final_odom[:2]).tolist(),
                    "error_true_mm": 1000 * result.error_true, "error_odom_mm": 1000 * result.error_odom,
                    "time_s": result.time_s, "wall_time_s": result.wall_time_s,
                    "real_time_factor": result.real_time_factor})
                if plot_dir and run == 0:
                    from ..viz.sim_plot import plot_run

                    plot_run(sim.scene.world, result, f"{plot_dir}/seed004_{_tag(target)}"
                             f"{'_obstacle' if obstacle else ''}.png")
    return rows


def _tag(target) -> str:
    return f"x{target[0]:+g}_y{target[1]:+g}".replace("+", "p").replace("-", "m")


SEED002_CELL, SEED002_WALL = 0.6, 0.1


@EXPERIMENTS.register("maze-astar")
@EXPERIMENTS.register("seed002")
def seed002(runs: int = 1, seed: int = 0, plot_dir: Optional[str] = ".", **_: Any) -> List[Dict[str, Any]]:
    """Mazes of 10×10 and 15×15 cells (0.6 m cells, 0.1 m walls, so 0.5 m
    corridors for the 0.21 m TurtleBot3 Burger; 0.05 m map resolution); from
    the centre of cell (0, 0) to the two far corners' cells; A* (octile) with
    Bresenham smoothing on the map inflated by the robot radius plus a
    margin for the grid's discretisation and the tracking error; the diff
    drive follows with goto_waypoint."""
    from ..control import GotoWaypoint
    from ..grid import make_maze, plan_world
    from ..grid.maze import maze_cell_center
    from ..robots import DiffDrive
    from .runner import PLAN_MARGIN
    from .simulation import Simulation

    rows = []
    robot = DiffDrive()
    for size in (10, 15):
        for run in range(runs):
            maze_seed = seed * 1000 + size * 10 + run
            grid = make_maze(size, size, seed=maze_seed, cell_size=SEED002_CELL, wall=SEED002_WALL, resolution=0.05)
            start = maze_cell_center(0, 0, SEED002_CELL, SEED002_WALL)
            for corner in ((size - 1, 0), (size - 1, size - 1)):
                goal = maze_cell_center(*corner, SEED002_CELL, SEED002_WALL)
                planned = plan_world(grid.inflate(robot.radius + PLAN_MARGIN), start, goal, algorithm="astar",
                                     heuristic="octile", smooth=True)
                row = {"experiment": "seed002", "maze": f"{size}x{size}", "maze_seed": maze_seed,
                       "start": list(start), "goal": list(goal), "plan_status": planned.status.name}
                if not planned.success:
                    rows.append(row | {"status": "NO_PATH", "reason": planned.reason})
                    continue
                path = np.vstack((start, planned.path[1:-1], goal)) if len(planned.path) > 2 else \
                    np.array((start, goal))
                heading = float(np.arctan2(*(path[1] - path[0])[::-1]))
                length = float(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1)))
                follower = GotoWaypoint(reach_radius=0.05)
                # generous: three times the time at cruise speed, plus turning
                sim = Simulation(grid, robot, follower, (*start, heading), goal, path=path, dt=0.05,
                                 max_time=3.0 * length / follower.speed + 60.0)
                result = sim.run(maze_seed)
                row |= {"status": result.status.name, "reason": result.reason, "time_s": result.time_s,
                        "path_length_m": length,
                        "waypoints": len(path), "travelled_m": result.distance,
                        "max_tracking_error_m": result.tracking_error(), "error_true_mm": 1000 * result.error_true,
                        "wall_time_s": result.wall_time_s, "real_time_factor": result.real_time_factor}
                if plot_dir:
                    from ..viz.sim_plot import plot_run

                    name = f"{plot_dir}/seed002_{size}x{size}_run{run + 1}_to_{corner[0]}_{corner[1]}.png"
                    plot_run(grid, result, name, raw_path=planned.tree.get("raw_cells") if planned.tree else None)
                    row["plot"] = name
                rows.append(row)
    return rows


#: the random-clutter worlds (:func:`random_clutter_world`): side [m], start, goal, obstacles; and the robot
#: hybrid-vs-field drives there
CLUTTER_SIDE, CLUTTER_START, CLUTTER_GOAL, CLUTTER_OBSTACLES = 10.0, (1.0, 1.0), (9.0, 9.0), 18
CLUTTER_ROBOT = "omni3"


def random_clutter_world(seed: int, obstacles: int = CLUTTER_OBSTACLES) -> World:
    """A 10 m × 10 m world from (1, 1) to (9, 9) (:data:`CLUTTER_SIDE` ...) with ``obstacles`` random
    circles (radius 0.2–0.7 m) and boxes (0.4–1.6 m sides), none within
    1.2 m of the start or the goal (seeded: the same seed, the same world)."""
    rng = np.random.default_rng(seed)
    start, goal = np.array(CLUTTER_START), np.array(CLUTTER_GOAL)
    shapes = []
    while len(shapes) < obstacles:
        c = rng.uniform(0.5, CLUTTER_SIDE - 0.5, 2)
        if min(np.hypot(*(c - start)), np.hypot(*(c - goal))) < 1.2:
            continue
        if rng.random() < 0.5:
            shapes.append(Circle((float(c[0]), float(c[1])), float(rng.uniform(0.2, 0.7))))
        else:
            half = rng.uniform(0.2, 0.8, 2)
            shapes.append(Rectangle(tuple(c - half), tuple(c + half)))
    return World(f"random_clutter_{seed}", Bounds(0.0, CLUTTER_SIDE, 0.0, CLUTTER_SIDE), CLUTTER_START, CLUTTER_GOAL,
                 tuple(shapes))


@EXPERIMENTS.register("hybrid-vs-field")
@EXPERIMENTS.register("random-clutter")
def hybrid_vs_field(runs: int = 20, seed: int = 0, **_: Any) -> List[Dict[str, Any]]:
    """The omni robot on ``runs`` seeded random cluttered worlds, with the
    plain potential field and with the hybrid navigator (defaults)."""
    from .runner import NoPathError, simulate

    rows = []
    for k in range(runs):
        world = random_clutter_world(seed * 1000 + k)
        for controller in ("potential_field", "hybrid"):
            try:
                result, _, sim = simulate(world, robot=CLUTTER_ROBOT, controller=controller, seed=k)
            except NoPathError as exc:  # a world whose passages are too narrow for the robot's plan
                rows.append({"experiment": "hybrid-vs-field", "world": world.name, "controller": controller,
                             "status": "NO_PATH", "reason": str(exc), "time_s": 0.0, "error_true_mm": None,
                             "min_clearance_m": None, "replans": 0, "wall_time_s": 0.0})
                continue
            rows.append({"experiment": "hybrid-vs-field", "world": world.name, "controller": controller,
                         "status": result.status.name, "time_s": result.time_s,
                         "error_true_mm": 1000 * result.error_true, "min_clearance_m": sim.min_clearance(result),
                         "replans": getattr(sim.controller, "replans", 0), "wall_time_s": result.wall_time_s})
    return rows


def hybrid_table(rows: List[Dict[str, Any]]) -> str:
    """What ran (a line: the table alone said nothing of it; newcomer, session 29), then reached, stalled
    and other endings with the mean time of the runs that reached, per controller."""
    worlds = len({r["world"] for r in rows})
    (sx, sy), (gx, gy) = CLUTTER_START, CLUTTER_GOAL
    lines = [f"The {CLUTTER_ROBOT} robot from ({sx:g}, {sy:g}) to ({gx:g}, {gy:g}) in "
             f"{counted(worlds, 'seeded random cluttered world')} ({CLUTTER_SIDE:g} m x {CLUTTER_SIDE:g} m, "
             f"{CLUTTER_OBSTACLES} circles and boxes), with the plain potential field and with the hybrid navigator:",
             f"{'controller':>16} {'reached':>8} {'stalled':>8} {'other':>6} {'mean time s':>12}"]
    for controller in ("potential_field", "hybrid"):
        group = [r for r in rows if r["controller"] == controller]
        reached = [r for r in group if r["status"] == "REACHED"]
        stalled = sum(r["status"] == "STALLED" for r in group)
        mean = np.mean([r["time_s"] for r in reached]) if reached else float("nan")
        lines.append(f"{controller:>16} {len(reached):>5}/{len(group):<2} {stalled:>8} "
                     f"{len(group) - len(reached) - stalled:>6} {mean:>12.1f}")
    return "\n".join(lines)


def seed004_table(rows: List[Dict[str, Any]]) -> str:
    """The seed's Tables 5–12 layout, one block per target and obstacle
    setting, with a mean-absolute-error row."""
    lines = []
    keys = []
    for r in rows:
        key = (tuple(r["target_mm"]), r["obstacle"])
        if key not in keys:
            keys.append(key)
    head = (f"{'No':>3} {'target X':>9} {'Y':>7} | {'true X':>8} {'Y':>8} {'error':>7} | "
            f"{'odom X':>8} {'Y':>8} {'error':>7} | {'time s':>6}  status")
    for target, obstacle in keys:
        group = [r for r in rows if tuple(r["target_mm"]) == target and r["obstacle"] == obstacle]
        lines.append(f"\nTarget ({target[0]:g}, {target[1]:g}) mm, {'with' if obstacle else 'without'} obstacle")
        lines.append(head)
        for r in group:
            tx, ty = r["final_true_mm"]
            ox, oy = r["final_odom_mm"]
            lines.append(f"{r['run']:>3} {target[0]:>9.0f} {target[1]:>7.0f} | {tx:>8.1f} {ty:>8.1f} "
                         f"{r['error_true_mm']:>7.1f} | {ox:>8.1f} {oy:>8.1f} {r['error_odom_mm']:>7.1f} | "
                         f"{r['time_s']:>6.2f}  {r['status']}")
        true_x, true_y = _mae(group, "final_true_mm", 0, target[0]), _mae(group, "final_true_mm", 1, target[1])
        odom_x, odom_y = _mae(group, "final_odom_mm", 0, target[0]), _mae(group, "final_odom_mm", 1, target[1])
        lines.append(f"{'MAE':>3} {'':>9} {'':>7} | {true_x:>8.1f} {true_y:>8.1f} "
                     f"{np.mean([r['error_true_mm'] for r in group]):>7.1f} | {odom_x:>8.1f} {odom_y:>8.1f} "
                     f"{np.mean([r['error_odom_mm'] for r in group]):>7.1f} | "
                     f"{np.mean([r['time_s'] for r in group]):>6.2f}  mean time")
    overall = [r["error_true_mm"] for r in rows]
    lines.append(f"\nAll {len(rows)} runs: {sum(r['status'] == 'REACHED' for r in rows)} reached; true error "
                 f"mean {np.mean(overall):.1f} mm (max {np.max(overall):.1f}); odometry's own error mean "
                 f"{np.mean([r['error_odom_mm'] for r in rows]):.1f} mm; time mean "
                 f"{np.mean([r['time_s'] for r in rows]):.2f} s")
    return "\n".join(lines).lstrip("\n")


def _mae(rows: List[Dict[str, Any]], key: str, axis: int, target: float) -> float:
    """Mean absolute error of one coordinate (mm) over runs."""
    return float(np.mean([abs(r[key][axis] - target) for r in rows]))


def seed002_table(rows: List[Dict[str, Any]]) -> str:
    head = f"{'maze':>6} {'goal':>14} {'status':>8} {'time s':>7} {'path m':>7} {'travelled m':>11} {'max track err m':>15}"
    lines = [head]
    for r in rows:
        goal = f"({r['goal'][0]:.2f}, {r['goal'][1]:.2f})"
        if r["status"] == "NO_PATH":
            lines.append(f"{r['maze']:>6} {goal:>14} {'NO_PATH':>8}  {r.get('reason', '')}")
            continue
        lines.append(f"{r['maze']:>6} {goal:>14} {r['status']:>8} {r['time_s']:>7.1f} {r['path_length_m']:>7.2f} "
                     f"{r['travelled_m']:>11.2f} {r['max_tracking_error_m']:>15.3f}")
    return "\n".join(lines)
