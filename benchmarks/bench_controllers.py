"""One control cycle of navlab's DWA and MPPI, beside PythonRobotics' DWA on the same inputs.

    python benchmarks/bench_controllers.py [--pythonrobotics DIR] [--repeat 100]

DIR is a checkout of github.com/AtsushiSakai/PythonRobotics (its
``PathPlanning/DynamicWindowApproach/dynamic_window_approach.py`` is imported
from there, never copied); without it only navlab's figures are printed.

The input: BARN world 0 (../shared/data/barn), the Jackal at (−2, 5.2)
heading +y at 0.3 m/s, its global path from the costmap planner.

- navlab ``dwa_barn``: 6 × 20 velocity samples in the window, 2 s rollouts at
  0.02 m steps, each scored with the footprint's cost on the costmap and the
  path/goal distance maps (computed each cycle, as base_local_planner does).
- PythonRobotics ``dwa_control``: configured to the same window (0.1–0.5 m/s,
  ±0.8 rad/s around the current turn rate), 6 × 20 samples, 2 s rollouts at
  0.04 s steps (the same 50 poses a rollout), the same rectangle, and the
  world's 209 cylinder centres as its obstacle points.
- navlab ``mppi``: Nav2's defaults, 2 000 sequences × 56 steps, all critics.

Medians over --repeat cycles (interleaved), with the load and the spread.
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from conditions import load_line, spread  # noqa: E402

BARN = Path(__file__).resolve().parents[2] / "shared" / "data" / "barn"
POSE = np.array((-2.0, 5.2, math.pi / 2))


def navlab_controllers():
    from navlab.control import make_controller
    from navlab.robots import make_robot
    from navlab.sim.runner import costmap_path
    from navlab.world import load_world
    from navlab.world.costmap import build_costmap

    world = load_world(str(BARN / "world_0.world"))
    robot = make_robot("jackal")
    out = {}
    for name, params in (("dwa_barn", {}), ("mppi", {})):
        ctrl = make_controller(name, **params)
        path = costmap_path(world, robot, ctrl, (-2, 3, 1.57), (-2, 13))
        ctrl.reset((-2, 13), path)
        settings = ctrl.costmap_settings
        ctrl.set_costmap(build_costmap(world, robot.shape, **settings), robot.shape)
        ctrl.velocity = np.array((0.3, 0.0, 0.0))
        if hasattr(ctrl, "seed"):
            ctrl.seed(np.random.default_rng(0))
        out[name] = ctrl
    return world, out


def pythonrobotics_dwa(folder: Path, world):
    path = folder / "PathPlanning" / "DynamicWindowApproach" / "dynamic_window_approach.py"
    if not path.is_file():
        return None
    import matplotlib

    matplotlib.use("Agg")
    spec = importlib.util.spec_from_file_location("pr_dwa", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    cfg = mod.Config()
    cfg.min_speed, cfg.max_speed = 0.1, 0.5
    cfg.max_yaw_rate = 1.57
    cfg.dt = 0.04
    cfg.max_accel = 10.0  # window ±0.4 m/s around 0.3: clipped to 0.1–0.5 as navlab's
    cfg.max_delta_yaw_rate = 20.0  # ±0.8 rad/s around 0
    cfg.v_resolution = (0.5 - 0.1) / 6 + 1e-9
    cfg.yaw_rate_resolution = 1.6 / 20 + 1e-9
    cfg.predict_time = 2.0 - 1e-9
    cfg.robot_type = mod.RobotType.rectangle
    cfg.robot_length, cfg.robot_width = 0.42, 0.33
    obstacles = np.array([o.center for o in world.obstacles])
    state = np.array((POSE[0], POSE[1], POSE[2], 0.3, 0.0))
    return lambda: mod.dwa_control(state, cfg, np.array((-2.0, 13.0)), obstacles)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pythonrobotics", type=Path, default=None, help="a PythonRobotics checkout")
    parser.add_argument("--repeat", type=int, default=100)
    args = parser.parse_args()
    world, ctrls = navlab_controllers()
    timed = {"navlab dwa_barn (6 × 20, 2 s)": lambda: ctrls["dwa_barn"].plan(0.0, POSE),
             "navlab mppi (2000 × 56)": lambda: ctrls["mppi"].plan(0.0, POSE)}
    pr = pythonrobotics_dwa(args.pythonrobotics, world) if args.pythonrobotics else None
    if pr is not None:
        timed["PythonRobotics dwa_control (6 × 20, 2 s)"] = pr
    print(load_line("before"))
    for fn in timed.values():
        fn()  # compile / warm
    samples = {k: [] for k in timed}
    for _ in range(args.repeat):
        for name, fn in timed.items():
            t0 = time.perf_counter()
            fn()
            samples[name].append(time.perf_counter() - t0)
    print(load_line("after"))
    med = {k: statistics.median(v) for k, v in samples.items()}
    for name, values in samples.items():
        print(f"{name:<44} median {1000 * med[name]:8.2f} ms  ({spread([1000 * v for v in values], 2, ' ms')}), "
              f"{1 / med[name]:7.0f} Hz")
    if pr is not None:
        ratio = med["PythonRobotics dwa_control (6 × 20, 2 s)"] / med["navlab dwa_barn (6 × 20, 2 s)"]
        print(f"navlab's DWA cycle is {ratio:.0f}× faster than PythonRobotics' on the same samples")
    print(f"navlab's MPPI cycle: {1 / med['navlab mppi (2000 × 56)']:.0f} Hz on one core "
          "(Nav2 states 50+ Hz for its C++ MPPI on a moderate CPU)")


if __name__ == "__main__":
    main()
