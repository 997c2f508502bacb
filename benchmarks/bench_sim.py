"""LiDAR scans and simulation steps against ir-sim, side by side.

    pip install -e . ir-sim==2.12.0
    python benchmarks/bench_sim.py [--repeat 200]

Three scenes, the same for both simulators:
- 21 circles (radius 0.25 m on a 7 × 3 lattice) in a 10 m × 10 m world,
  an omni robot at (5, 5) with a 360-beam LiDAR (range 12 m);
- the same plus five moving circles (radius 0.2 m, 0.3 m/s, crossing the
  world: navlab `velocity` motions reflecting at the bounds, ir-sim omni
  obstacles with the `dash` behaviour towards a goal);
- a 219 × 183-cell maze grid (0.05 m cells) with the same LiDAR.

ir-sim reads the circles from its YAML world file and the maze from a PNG
(`obstacle_map`); it runs headless (no display, no animation). We time its
LiDAR alone (`lidar.step`) and a whole `env.step()`; navlab's scan alone
(`Lidar.exact`) and a whole simulator step (kinematics, encoders, LiDAR and
the potential field), taken from a 600-step run. Prints medians and ratios.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time

import numpy as np

CIRCLES = [(1.5 + 1.2 * i, 2.0 + 3.0 * j, 0.25) for i in range(7) for j in range(3)]
#: five moving circles: start, goal (ir-sim dashes there; navlab keeps the velocity and reflects)
MOVERS = [((0.6, 3.5), (9.4, 3.5)), ((9.4, 6.5), (0.6, 6.5)), ((2.0, 9.4), (2.0, 0.6)),
          ((8.0, 0.6), (8.0, 9.4)), ((0.6, 0.6), (9.4, 9.4))]
MOVER_RADIUS, MOVER_SPEED = 0.2, 0.3


def median_time(fn, repeat: int) -> float:
    fn()
    samples = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        samples.append(time.perf_counter() - t0)
    return statistics.median(samples)


def irsim_env(folder: str, obstacle_map: str | None, moving: bool = False):
    import irsim

    lines = ["world:", "  height: 10", "  width: 10", "  step_time: 0.05", "  sample_time: 0.05",
             "  collision_mode: 'unobstructed'"]
    if obstacle_map:
        lines += [f"  obstacle_map: '{obstacle_map}'", "  height: 9.15", "  width: 10.95"]
        lines = [ln for ln in lines if ln not in ("  height: 10", "  width: 10")]
    start = "[0.4, 0.4, 0]" if obstacle_map else "[5.0, 0.6, 0]"
    lines += ["robot:", "  - kinematics: {name: 'omni'}", "    shape: {name: 'circle', radius: 0.16}",
              f"    state: {start}", "    goal: [9, 9, 0]", "    vel_max: [0.3, 0.3]",
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
    path = os.path.join(folder, "world.yaml")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return irsim.make(path, display=False, save_ani=False, log_level="ERROR")


def navlab_step_time(scene, start, goal) -> float:
    from navlab.control import PotentialField
    from navlab.robots import Omni3
    from navlab.sensors import Lidar
    from navlab.sim import Simulation

    sim = Simulation(scene, Omni3(), PotentialField(stall_window=1e9), start, goal, lidar=Lidar(), max_time=30.0)
    sim.run(0)
    best = []
    for seed in range(3):
        r = sim.run(seed)
        best.append(r.wall_time_s / max(r.steps, 1))
    print(f"  navlab run on {scene.name if hasattr(scene, 'name') else 'maze'}: {r.status.name} after {r.steps} steps")
    return min(best)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=200)
    args = ap.parse_args()
    from PIL import Image

    from navlab.grid import make_maze
    from navlab.sensors import Lidar
    from navlab.world import World
    from navlab.world.shapes import Circle
    from navlab.world.world import Bounds

    from navlab.world.motion import ConstantVelocity

    world = World("circles", Bounds(0, 10, 0, 10), (5.0, 0.6), (5.0, 9.4), tuple(Circle((x, y), r) for x, y, r in CIRCLES))
    movers = tuple(Circle(a, MOVER_RADIUS, motion=ConstantVelocity(tuple(MOVER_SPEED * (np.subtract(b, a))
                                                                          / np.hypot(*np.subtract(b, a)))))
                   for a, b in MOVERS)
    moving_world = World("moving", world.bounds, world.start, world.goal, world.obstacles + movers)
    maze = make_maze(18, 15, seed=4, cell_size=0.6, wall=0.15, resolution=0.05)
    print(f"maze grid: {maze.width} x {maze.height} cells")
    lidar = Lidar()
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        png = os.path.join(folder, "maze.png")
        Image.fromarray(np.where(maze.blocked[::-1], 0, 255).astype(np.uint8)).save(png)
        for name, scene, start, goal, obstacle_map, moving in (
                ("21 circles", world, (5.0, 0.6, 0.0), (5.0, 9.4), None, False),
                ("+5 moving", moving_world, (5.0, 0.6, 0.0), (5.0, 9.4), None, True),
                ("maze grid", maze, (0.4, 0.4, 0.0), (10.5, 8.7), png, False)):
            pose = np.array(start)
            nav_scan = median_time(lambda: lidar.exact(scene, pose), args.repeat)
            nav_step = navlab_step_time(scene, start, goal)
            try:
                env = irsim_env(folder, obstacle_map, moving)
            except ImportError:
                print("ir-sim not installed (pip install ir-sim==2.12.0): navlab figures only")
                rows.append((name, nav_scan, None, nav_step, None))
                continue
            robot = env.robot
            sensor = robot.sensors[0]
            n = max(10, args.repeat // (20 if obstacle_map else 1))
            ir_scan = median_time(lambda: sensor.step(robot.state), n)
            ir_step = median_time(env.step, n)
            valid = sensor.valid
            same_beams = Lidar()
            same_beams.angles = np.asarray(sensor.angle_list, float)  # ir-sim: −π..π inclusive
            ours = same_beams.exact(scene, np.array((*robot.state[:2, 0], robot.state[2, 0])))
            theirs = np.where(valid, sensor.range_data, np.inf)
            both = np.isfinite(ours) & np.isfinite(theirs)
            # (moving obstacles have moved on in ir-sim while its step was timed: nothing to compare)
            agree = np.max(np.abs(ours[both] - theirs[both])) if both.any() and not moving else float("nan")
            rows.append((name, nav_scan, ir_scan, nav_step, ir_step, agree))
            env.end(0) if hasattr(env, "end") else None
    print(f"{'scene':<12} {'navlab scan':>12} {'ir-sim scan':>12} {'ratio':>7} {'navlab step':>12} "
          f"{'ir-sim step':>12} {'ratio':>7}  max |Δrange| where both hit")
    for row in rows:
        name, ns, irs, nst, irst = row[:5]
        if irs is None:
            print(f"{name:<12} {ns * 1e3:>10.3f}ms {'-':>12} {'-':>7} {nst * 1e3:>10.3f}ms")
            continue
        print(f"{name:<12} {ns * 1e3:>10.3f}ms {irs * 1e3:>10.3f}ms {irs / ns:>6.0f}x {nst * 1e3:>10.3f}ms "
              f"{irst * 1e3:>10.3f}ms {irst / nst:>6.0f}x  {row[5]:.2e} m")


if __name__ == "__main__":
    main()
