"""LiDAR scans and simulation steps against ir-sim, side by side.

    pip install -e '.[irsim]'          # ir-sim==2.12.0; without it only navlab's figures are printed
    python benchmarks/bench_sim.py [--rounds 7] [--repeat 100] [--irsim-calls 20]

Three scenes, the same for both simulators:
- 21 circles (radius 0.25 m on a 7 × 3 lattice) in a 10 m × 10 m world,
  an omni robot at (5, 0.6) with a 360-beam LiDAR (range 12 m);
- the same plus five moving circles (radius 0.2 m, 0.3 m/s, crossing the
  world: navlab `velocity` motions reflecting at the bounds, ir-sim omni
  obstacles with the `dash` behaviour towards a goal);
- a 219 × 183-cell maze grid (0.05 m cells) with the same LiDAR.

ir-sim reads the circles from its YAML world file and the maze from a PNG
(`obstacle_map`); it runs headless (no display, no animation). We time its
LiDAR alone (`lidar.step`, median of --irsim-calls calls) and a whole
`env.step()` (median of --irsim-calls steps from its reset state); navlab's
scan alone (`Lidar.exact`, median of --repeat scans) and a whole simulator
step (kinematics, encoders, LiDAR and the potential field: the mean step of
a 600-step run, wall and CPU time). On the maze ir-sim's calls take about
0.1 s each, so it makes a fifth as many there.

The machine is shared: each figure is measured once a round, navlab and
ir-sim alternating (who goes first swaps every round), and the table gives
the median over --rounds rounds with its range (min–max of the rounds), the
load at start and end, and the ratio of the medians. The CPU time of
navlab's step (this thread's, over the whole run, whose set-up is under
0.3 % of it) moves less with the load than its wall time does. The last
column compares the two LiDARs' ranges from where ir-sim's robot starts
(ir-sim approximates circles by polygons).
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import tempfile
import time
from functools import partial

import numpy as np

from conditions import load_line, spread

CIRCLES = [(1.5 + 1.2 * i, 2.0 + 3.0 * j, 0.25) for i in range(7) for j in range(3)]
#: five moving circles: start, goal (ir-sim dashes there; navlab keeps the velocity and reflects)
MOVERS = [((0.6, 3.5), (9.4, 3.5)), ((9.4, 6.5), (0.6, 6.5)), ((2.0, 9.4), (2.0, 0.6)),
          ((8.0, 0.6), (8.0, 9.4)), ((0.6, 0.6), (9.4, 9.4))]
MOVER_RADIUS, MOVER_SPEED = 0.2, 0.3


def median_time(fn, repeat: int) -> float:
    """Median wall seconds of ``repeat`` calls, after one untimed call."""
    fn()
    samples = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        samples.append(time.perf_counter() - t0)
    return statistics.median(samples)


def irsim_env(folder: str, obstacle_map: str | None, start, goal, moving: bool = False):
    """A headless ir-sim environment of one scene, from a YAML world file written into ``folder``; its
    robot starts at ``start`` (x, y, θ) and dashes to ``goal`` (x, y), navlab's own query."""
    import irsim

    lines = ["world:", "  height: 10", "  width: 10", "  step_time: 0.05", "  sample_time: 0.05",
             "  collision_mode: 'unobstructed'"]
    if obstacle_map:
        lines += [f"  obstacle_map: '{obstacle_map}'", "  height: 9.15", "  width: 10.95"]
        lines = [ln for ln in lines if ln not in ("  height: 10", "  width: 10")]
    lines += ["robot:", "  - kinematics: {name: 'omni'}", "    shape: {name: 'circle', radius: 0.16}",
              f"    state: [{start[0]}, {start[1]}, {start[2]}]", f"    goal: [{goal[0]}, {goal[1]}, 0]",
              "    vel_max: [0.3, 0.3]",
              "    behavior: {name: 'dash'}",
              "    sensors:", "      - type: 'lidar2d'", "        range_min: 0.15", "        range_max: 12",
              "        angle_range: 6.283185307179586", "        number: 360", "        noise: False"]
    if not obstacle_map:
        lines += ["obstacle:"]
        for x, y, r in CIRCLES:
            lines += [f"  - shape: {{name: 'circle', radius: {r}}}", f"    state: [{x}, {y}, 0]"]
        for (x, y), (gx, gy) in MOVERS if moving else ():
            lines += [f"  - shape: {{name: 'circle', radius: {MOVER_RADIUS}}}", f"    state: [{x}, {y}, 0]",
                      "    kinematics: {name: 'omni'}", "    behavior: {name: 'dash'}",
                      f"    vel_max: [{MOVER_SPEED}, {MOVER_SPEED}]", f"    goal: [{gx}, {gy}, 0]"]
    path = os.path.join(folder, f"world{'_map' if obstacle_map else ''}{'_moving' if moving else ''}.yaml")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return irsim.make(path, display=False, save_ani=False, log_level="ERROR")


def navlab_simulation(scene, start, goal):
    """The simulator run that is timed: omni robot, potential field, 360-beam LiDAR, 600 steps of 0.05 s."""
    from navlab.control import PotentialField
    from navlab.robots import Omni3
    from navlab.sensors import Lidar
    from navlab.sim import Simulation

    # stall_window=1e9: the field never gives up, so every run is 600 steps long
    sim = Simulation(scene, Omni3(), PotentialField(stall_window=1e9), start, goal, lidar=Lidar(), max_time=30.0)
    first = sim.run(0)  # kernels loaded before any timing
    print(f"  navlab run on {getattr(scene, 'name', 'maze')}: {first.status.name} after {first.steps} steps")
    return sim


def navlab_step_time(sim, seed: int) -> tuple[float, float]:
    """Wall and CPU seconds of the mean step of one run (the wall time is the simulator's own, its loop only)."""
    c0 = time.thread_time()
    result = sim.run(seed)
    steps = max(result.steps, 1)
    return result.wall_time_s / steps, (time.thread_time() - c0) / steps


def build_scenes():
    """(name, navlab scene, start, goal, maze grid or None, moving) of the three scenes."""
    from navlab.grid import make_maze
    from navlab.world import World
    from navlab.world.motion import ConstantVelocity
    from navlab.world.shapes import Circle
    from navlab.world.world import Bounds

    world = World("circles", Bounds(0, 10, 0, 10), (5.0, 0.6), (5.0, 9.4),
                  tuple(Circle((x, y), r) for x, y, r in CIRCLES))
    movers = tuple(Circle(a, MOVER_RADIUS, motion=ConstantVelocity(tuple(MOVER_SPEED * (np.subtract(b, a))
                                                                          / np.hypot(*np.subtract(b, a)))))
                   for a, b in MOVERS)
    moving_world = World("moving", world.bounds, world.start, world.goal, world.obstacles + movers)
    maze = make_maze(18, 15, seed=4, cell_size=0.6, wall=0.15, resolution=0.05)
    print(f"maze grid: {maze.width} x {maze.height} cells")
    return (("21 circles", world, (5.0, 0.6, 0.0), (5.0, 9.4), None, False),
            ("+5 moving", moving_world, (5.0, 0.6, 0.0), (5.0, 9.4), None, True),
            ("maze grid", maze, (0.4, 0.4, 0.0), (10.5, 8.7), maze, False))


def range_agreement(env, scene) -> float:
    """Largest |navlab range − ir-sim range| over the beams where both hit, from where ir-sim's robot starts
    (its environment reset: moving obstacles where both simulators start them, at t = 0)."""
    from navlab.sensors import Lidar

    env.reset()  # also scans (ir-sim refreshes its sensors on reset)
    robot = env.robot
    sensor = robot.sensors[0]
    same_beams = Lidar()
    same_beams.angles = np.asarray(sensor.angle_list, float)  # ir-sim: −π..π inclusive
    ours = same_beams.exact(scene, np.array((*robot.state[:2, 0], robot.state[2, 0])))
    theirs = np.where(sensor.valid, sensor.range_data, np.inf)
    both = np.isfinite(ours) & np.isfinite(theirs)
    return float(np.max(np.abs(ours[both] - theirs[both]))) if both.any() else float("nan")


def irsim_scan_time(env, calls: int) -> float:
    """Median seconds of ir-sim's LiDAR alone, scanning from where its robot is."""
    sensor = env.robot.sensors[0]
    return median_time(lambda: sensor.step(env.robot.state), calls)


def irsim_step_time(env, calls: int) -> float:
    """Median seconds of ir-sim's whole step, from its reset state (each round steps the same stretch)."""
    env.reset()
    return median_time(env.step, calls)


def one_round(k: int, scenes, sims, envs, args) -> dict:
    """Every figure of every scene once, navlab and ir-sim alternating (round ``k`` odd: ir-sim first)."""
    from navlab.sensors import Lidar

    lidar = Lidar()
    out = {}
    for (name, scene, start, _, grid, _), sim, env in zip(scenes, sims, envs):
        timers = {"navlab": {"scan": partial(median_time, partial(lidar.exact, scene, np.array(start)), args.repeat),
                             "step": partial(navlab_step_time, sim, k)},
                  "ir-sim": {}}
        if env is not None:
            calls = max(3, args.irsim_calls // (5 if grid is not None else 1))
            timers["ir-sim"] = {"scan": partial(irsim_scan_time, env, calls),
                                "step": partial(irsim_step_time, env, calls)}
        order = ("navlab", "ir-sim") if k % 2 == 0 else ("ir-sim", "navlab")
        figures = {f"{tool} {what}": timers[tool][what]()
                   for what in ("scan", "step") for tool in order if what in timers[tool]}
        figures["navlab step"], figures["navlab step CPU"] = figures["navlab step"]  # (wall, CPU)
        out[name] = figures
    return out


def irsim_envs(scenes, folder: str) -> list:
    """One headless ir-sim environment per scene (the maze read from a PNG), or Nones without ir-sim."""
    from PIL import Image

    envs = []
    for _, _, start, goal, grid, moving in scenes:
        png = None
        if grid is not None:
            png = os.path.join(folder, "maze.png")
            Image.fromarray(np.where(grid.blocked[::-1], 0, 255).astype(np.uint8)).save(png)
        try:
            envs.append(irsim_env(folder, png, start, goal, moving))
        except ImportError:
            print("ir-sim not installed (pip install -e '.[irsim]'): navlab figures only")
            return [None] * len(scenes)
    return envs


def cell(seconds) -> str:
    """``median (min–max) ms`` of one figure over the rounds."""
    if not seconds:
        return "-"
    ms = [1e3 * s for s in seconds]
    digits = 3 if statistics.median(ms) < 1 else 2 if statistics.median(ms) < 10 else 1
    return f"{statistics.median(ms):.{digits}f} ({spread(ms, digits)}) ms"


def ratio(slow, fast) -> str:
    """The ratio of the medians of two figures' rounds (ir-sim's over navlab's)."""
    return f"{statistics.median(slow) / statistics.median(fast):.0f}x" if slow and fast else "-"


def report(rounds, scenes, agreement) -> None:
    """The two tables: scans, then whole steps; medians over the rounds with their ranges."""
    def values(name, figure):
        return [r[name][figure] for r in rounds if figure in r[name]]

    print(f"\n{'scene':<12} {'navlab scan':>24} {'ir-sim scan':>24} {'ratio':>7}")
    for name, *_ in scenes:
        ours, theirs = values(name, "navlab scan"), values(name, "ir-sim scan")
        print(f"{name:<12} {cell(ours):>24} {cell(theirs):>24} {ratio(theirs, ours):>7}")
    print(f"\n{'scene':<12} {'navlab step (wall)':>24} {'navlab step (CPU)':>24} {'ir-sim step':>24} {'ratio':>7}  "
          "max |Δrange| where both hit")
    for name, *_ in scenes:
        ours, theirs = values(name, "navlab step"), values(name, "ir-sim step")
        print(f"{name:<12} {cell(ours):>24} {cell(values(name, 'navlab step CPU')):>24} {cell(theirs):>24} "
              f"{ratio(theirs, ours):>7}  {'-' if math.isnan(agreement[name]) else f'{agreement[name]:.2e} m'}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=7,
                    help="interleaved rounds (default 7); each figure is measured once a round, and the table gives "
                         "the median over the rounds and their range")
    ap.add_argument("--repeat", type=int, default=100,
                    help="navlab scans timed a round (default 100; their median is the round's figure)")
    ap.add_argument("--irsim-calls", type=int, default=20,
                    help="ir-sim scans and steps timed a round (default 20, a fifth of it on the maze, where each "
                         "takes about 0.1 s; their median is the round's figure)")
    args = ap.parse_args()
    if min(args.rounds, args.repeat, args.irsim_calls) < 1:
        ap.error("--rounds, --repeat and --irsim-calls must be at least 1")
    print(load_line("at start"))
    scenes = build_scenes()
    sims = [navlab_simulation(scene, start, goal) for _, scene, start, goal, _, _ in scenes]
    with tempfile.TemporaryDirectory() as folder:
        envs = irsim_envs(scenes, folder)
        rounds = [one_round(k, scenes, sims, envs, args) for k in range(args.rounds)]
        agreement = {name: float("nan") if env is None else range_agreement(env, scene)
                     for (name, scene, *_), env in zip(scenes, envs)}
        for env in envs:
            if env is not None:
                env.end(0)
    print(f"\n{args.rounds} rounds, navlab and ir-sim alternating; each cell: median (min–max over the rounds); "
          "ratio: ir-sim's median over navlab's")
    report(rounds, scenes, agreement)
    print(load_line("at end"))


if __name__ == "__main__":
    main()
