"""``navlab list``: every registered part, with its description and parameters."""

from __future__ import annotations

import inspect
import shutil
import textwrap
from typing import Any, Callable, Dict, Iterator, List, Optional, Tuple

import click

from ..registry import Registry, parameters_of
from ..wording import counted
from .common import SuggestingChoice, before_numba_import

NAME_WIDTH = 20  #: [characters] the name column
#: parameters of a grid search other than the query itself (shown for every grid planner)
_GRID_QUERY = ("grid", "start", "goal", "algorithm")


def first_paragraph(text: Optional[str]) -> str:
    """The first paragraph of a docstring (or a registry's description), on one line."""
    lines = inspect.cleandoc(text or "").splitlines()
    paragraph: List[str] = []
    for line in lines:
        if not line.strip():
            if paragraph:
                break
            continue
        paragraph.append(line.strip())
    return " ".join(paragraph).replace("``", "")  # reST literals read as plain text in a terminal


def _entry(name: str, description: str, details: str = "") -> Iterator[str]:
    """A name and its wrapped description, then the details indented under it."""
    width = max(60, min(shutil.get_terminal_size((100, 24)).columns, 120))
    indent = " " * (2 + NAME_WIDTH + 1)
    yield textwrap.fill(description or "(no description)", width=width, initial_indent=f"  {name:<{NAME_WIDTH}} ",
                        subsequent_indent=indent, break_on_hyphens=False)
    if details:
        yield textwrap.fill(details, width=width, initial_indent=indent, subsequent_indent=indent + "  ",
                            break_on_hyphens=False)


def _params(factory: Callable[..., Any], skip: Tuple[str, ...] = ()) -> str:
    params = {k: v for k, v in parameters_of(factory).items() if k not in skip}
    return ", ".join(f"{k}={v!r}" for k, v in params.items()) or "(no parameters)"


def _from_registry(registry: Registry, params: bool = True) -> Iterator[str]:
    """One entry per registered object, under its own name (the last it was
    registered under), with its other names as aliases."""
    names: Dict[int, List[str]] = {}
    for name in registry:
        names.setdefault(id(registry.get(name)), []).append(name)
    for name in registry:
        factory = registry.get(name)
        if getattr(factory, "registered_name", name) != name:
            continue  # an alias: listed with its object's own name
        aliases = [n for n in names[id(factory)] if n != name]
        description = first_paragraph(factory.__doc__) + (f" (alias: {', '.join(aliases)})" if aliases else "")
        yield from _entry(name, description, _params(factory) if params else "")


def _tree_planners() -> Iterator[str]:
    from ..sampling import PLANNERS

    yield from _from_registry(PLANNERS)
    yield "  (None: derived from the world, see the docs)"


def _grid_planners() -> Iterator[str]:
    from ..grid.planner import GRID_ALGORITHMS, HEURISTICS, as_searched, plan

    # what navlab plan takes (smooth_method is grid.plan's alone: navlab plan smooths by supercover), with each
    # algorithm's own heuristic and weight where it has them (dijkstra was listed with heuristic='octile')
    defaults = {k: v for k, v in parameters_of(plan).items() if k not in _GRID_QUERY + ("smooth_method",)}
    for name in GRID_ALGORITHMS:
        own = {**defaults, **as_searched(name, **{k: defaults[k] for k in ("heuristic", "weight")})}
        yield from _entry(name, first_paragraph(GRID_ALGORITHMS.get(name)),
                          ", ".join(f"{k}={v!r}" for k, v in own.items()))
    yield from _entry("(heuristics)", f"for astar's heuristic=: {', '.join(HEURISTICS)}")
    yield from _entry("(costmap)", "astar with costmap=true plans on a Nav2-style costmap (docs/grid.md), with "
                                   "inflation_radius=0.55, cost_scaling_factor=3.0, cost_travel_multiplier=2.0, "
                                   "allow_unknown=false and resolution (a geometric world's, default 0.05 m)")


def _pose_planners() -> Iterator[str]:
    from ..grid.hybrid_astar import plan_hybrid
    from ..pose_queries import TREE_POSE_PLANNERS

    yield from _entry("hybrid_astar", "Hybrid A* between poses for a car-like robot (Dolgov et al. 2008; Nav2 Smac "
                      "Hybrid) on the source's occupancy grid; not `navlab grid plan`.",
                      "footprint=None (the world's, else a disc of its robot radius), turning_radius=None (the "
                      "scene's, else 0.4), " + _params(plan_hybrid, skip=("grid", "start", "goal", "turning_radius",
                                                                         "footprint", "robot_radius")))
    yield from _entry("(trees)", f"{', '.join(TREE_POSE_PLANNERS)} plan between poses too with "
                      "--param motion=dubins or motion=reeds_shepp (turning_radius=R)")


def _samplers() -> Iterator[str]:
    from ..sampling import SAMPLERS

    yield from _from_registry(SAMPLERS)


def _scenes() -> Iterator[str]:
    from ..world import SCENES

    for name in SCENES:
        factory = SCENES.get(name)
        w = factory()
        robot = (f"footprint {w.footprint.describe()}, turning radius {w.meta.get('turning_radius')} m"
                 if w.footprint is not None else f"robot radius {w.robot_radius} m")
        start = w.start if w.start_heading is None else (*w.start, round(w.start_heading, 4))
        goal = w.goal if w.goal_heading is None else (*w.goal, round(w.goal_heading, 4))
        yield from _entry(name, first_paragraph(factory.__doc__),
                          f"start {start}, goal {goal}, {robot}, {counted(len(w.obstacles), 'obstacle')}")


def _controllers() -> Iterator[str]:
    from ..control.base import CONTROLLERS

    yield from _from_registry(CONTROLLERS)


def _robots() -> Iterator[str]:
    from ..robots.kinematics import ROBOTS

    yield from _from_registry(ROBOTS)


def _lidar_models() -> Iterator[str]:
    from ..sensors.lidar import NOISE_MODELS

    yield from _from_registry(NOISE_MODELS)


def _suites() -> Iterator[str]:
    from ..bench.errors import ExperimentError
    from ..bench.suites import BARN_SUITE, SUITES

    for name in SUITES:
        suite = SUITES.get(name)
        try:
            data = suite()
        except ExperimentError as exc:  # a suite on data that is not here (the Moving AI maps): listed all the same
            needs = str(exc).split(" (")[0]
            yield from _entry(name, first_paragraph(suite.__doc__), f"not runnable here: {needs}; "
                                                                     f"`navlab bench --suite {name}` says more")
            continue
        counts = [(len(data.get(k) or []), k) for k in ("worlds", "planners", "samplers") if k in data]
        sizes = ", ".join(f"{n} {k if n != 1 else k[:-1]}" for n, k in counts)
        yield from _entry(name, first_paragraph(suite.__doc__), sizes + f"; `navlab bench --suite {name}`")
    yield from _entry(BARN_SUITE[0], BARN_SUITE[1], "`navlab bench --suite barn --data DIR --controller NAME`")


def _executors() -> Iterator[str]:
    from ..bench.executors import EXECUTORS

    yield from _from_registry(EXECUTORS, params=False)


def _experiments() -> Iterator[str]:
    from ..sim import latency  # noqa: F401 - registers sensor-latency
    from ..sim.experiments import EXPERIMENTS

    yield from _from_registry(EXPERIMENTS)


#: kind → (title, the lines listing it); `navlab list KIND` shows one kind
KINDS: Dict[str, Tuple[str, Callable[[], Iterator[str]]]] = {
    "planners": ("planners (sampling-based, on worlds and maps)", _tree_planners),
    "grid": ("grid planners (on occupancy grids; `navlab grid plan --algorithm`)", _grid_planners),
    "pose": ("pose planners (car-like robots, between poses x y theta; `navlab plan --planner NAME`)",
             _pose_planners),
    "samplers": ("samplers (for the sampling-based planners)", _samplers),
    "scenes": ("scenes (built-in worlds)", _scenes),
    "controllers": ("controllers (`navlab sim`)", _controllers),
    "robots": ("robots (`navlab sim`)", _robots),
    "lidar": ("LiDAR noise models", _lidar_models),
    "suites": ("bench suites (`navlab bench --suite`)", _suites),
    "executors": ("bench executors (`navlab bench --executor`)", _executors),
    "experiments": ("sim experiments (`navlab sim --experiment`)", _experiments),
}


@click.command("list")
@click.argument("kind", required=False, metavar="[KIND]", type=SuggestingChoice(list(KINDS)))
def list_cmd(kind: Optional[str]) -> None:
    """Every registered part with its description and parameters (defaults shown).

    KIND limits the list to one kind: planners, grid, pose, samplers, scenes,
    controllers, robots, lidar, suites, executors or experiments.
    """
    before_numba_import()  # the registries live beside the kernels, so listing imports numba
    for i, key in enumerate([kind] if kind else list(KINDS)):
        title, lines = KINDS[key]
        if i:
            click.echo("")
        click.echo(f"{title}:")
        for line in lines():
            click.echo(line)
