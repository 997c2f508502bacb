"""Experiments as data: worlds × planners × samplers × parameter grid × trials.

An experiment is a mapping (usually a YAML file)::

    name: my-study
    worlds: [clutter, trap, my_world.yaml]     # scene names or world files
    planners: [rrt_star, {name: rrt, expand_dis: 0.5, label: rrt-0.5}, ompl:RRTstar]
    samplers: [uniform, {name: goal_bias, goal_sample_rate: 0.05}]
    params: {connect_circle_dist: 30}           # given to every cell
    grid: {expand_dis: [0.5, 1.0]}              # every combination is a cell
    budget: {max_iter: 5000, max_time: null}
    trials: 20
    seed: 0

Relative world paths in a file are read from the file's folder. A *cell* is one combination; its trials get seeds derived from the base seed
and the cell's identity (not its position in the file, nor the number of
trials), so any trial can be rerun alone and adding trials later keeps the
earlier ones.
"""

from __future__ import annotations

import datetime
import functools
import hashlib
import itertools
import json
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, Iterator, List, Optional, Tuple, Union

import numpy as np

from ..limits import MAX_COUNT, check_flag, digit_count, is_finite_real, plain_values, shown, value_text
from ..registry import suggest
from ..wording import listed
from .errors import ExperimentError
from ..yamlio import read_yaml

OMPL_PREFIX = "ompl:"
#: the most cells (combinations) and trials one run may have: each trial is a
#: row kept in memory (for the statistics at the end) and in results.jsonl.
#: Measured: 8–20 KB of memory per trial (2 000 trials 179 MB peak, 20 000
#: trials 329 MB; an outside run of the old 10⁶ limit reached 2.25 GB at
#: 11 %), so 10⁵ trials stay within 2 GB. Larger studies: several runs, or
#: --resume with more trials in the same folder.
MAX_CELLS = 10_000
MAX_TRIALS = 100_000
#: [bytes] largest experiment file read
MAX_FILE_BYTES = 2 * 2**20
FIELDS = ("name", "description", "worlds", "planners", "samplers", "params", "grid", "budget", "trials", "seed",
          "claims", "study")
#: fields that describe an experiment without changing its results
DESCRIPTIVE = ("trials", "description", "name", "claims", "study")
#: an experiment's samplers when it names none (its tree planners draw uniformly), and its seed
DEFAULT_SAMPLERS = ("uniform",)
DEFAULT_SEED = 0
#: trials of each cell run a second time, late in the run, to measure how
#: much the timing of identical work varies (the noise the time verdicts must beat)
NOISE_REPEATS = 2
CLAIM_FIELDS = ("text", "metric", "lower", "higher")
BUDGET_FIELDS = ("max_iter", "max_time")
CLAIM_METRICS = ("cost", "time_s", "iterations", "first_solution_iteration", "vs_optimum", "vs_theta")


@dataclass(frozen=True)
class Component:
    """A planner or sampler by registered name, with its settings."""

    name: str
    params: Dict[str, Any] = field(default_factory=dict)
    label: str = ""

    @property
    def title(self) -> str:
        return self.label or self.name

    def to_dict(self) -> Dict[str, Any]:
        return {"name": self.name, "params": dict(self.params), "label": self.title}


@dataclass(frozen=True)
class Cell:
    """One combination of world, planner, sampler and grid point."""

    world: str
    planner: Component
    sampler: Optional[Component]  #: None for OMPL planners (they sample themselves)
    params: Dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> Dict[str, Any]:
        return {"world": self.world, "planner": self.planner.to_dict(),
                "sampler": self.sampler.to_dict() if self.sampler else None, "params": dict(self.params)}

    @property
    def cell_id(self) -> str:
        return stable_hash(self.to_dict())[:12]

    @property
    def label(self) -> str:
        parts = [self.world, self.planner.title, self.sampler.title if self.sampler else "-"]
        parts += [f"{k}={v}" for k, v in sorted(self.params.items())]
        return " / ".join(parts)


def samples(planner: str) -> bool:
    """Whether ``planner`` takes a navlab sampler (tree planners do; grid
    algorithms search and OMPL's planners sample by themselves)."""
    from ..grid.planner import GRID_ALGORITHMS
    from ..pose_queries import POSE_PLANNERS

    return not planner.startswith(OMPL_PREFIX) and planner not in GRID_ALGORITHMS and planner not in POSE_PLANNERS


def stable_hash(data: Any) -> str:
    """SHA-256 of the canonical JSON of ``data``."""
    return hashlib.sha256(json.dumps(data, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def trial_seed(base_seed: int, cell_id: str, trial: int) -> int:
    """The seed of one trial: a function of the base seed, the cell and the
    trial index only (numpy SeedSequence, so neighbouring seeds are unrelated)."""
    seq = np.random.SeedSequence(entropy=int(base_seed), spawn_key=(int(cell_id[:8], 16), int(trial)))
    return int(seq.generate_state(1, np.uint32)[0])


@dataclass
class Experiment:
    """A validated experiment definition (see the module docstring)."""

    name: str
    worlds: List[str]
    planners: List[Component]
    samplers: List[Component]
    params: Dict[str, Any] = field(default_factory=dict)
    grid: Dict[str, List[Any]] = field(default_factory=dict)
    budget: Dict[str, Any] = field(default_factory=dict)
    trials: int = 20
    seed: int = 0
    description: str = ""
    #: hypotheses to test: ``{text, metric, lower, higher}`` with group labels
    #: (``sampler`` or ``planner`` titles; ``lower`` may be a list)
    claims: List[Dict[str, Any]] = field(default_factory=list)
    #: the study a suite reproduces: ``{title, measured, reference: [...]}`` (report header)
    study: Dict[str, Any] = field(default_factory=dict)
    #: map worlds by name: ``{name, map, robot_radius, queries}`` (see :mod:`navlab.bench.maps`)
    maps: Dict[str, Dict[str, Any]] = field(default_factory=dict)
    #: whether the document named its samplers (else ``uniform``, for the tree planners if any)
    samplers_given: bool = True

    def cells(self) -> List[Cell]:
        """Every cell once. A planner's cells carry only the swept values it takes (:func:`routed_params`;
        its own setting of the same name wins): ``grid: {expand_dis: [1, 2]}`` gave hybrid_astar two cells
        that ran the same search as if expand_dis had mattered (newcomer, session 22);
        :meth:`unswept` names what each planner ignores."""
        kinds = []  # (planner, sampler, settings), the same in every world: routed once
        for planner, sampler, point, own, routed in self._routings():
            kept = _taken(planner.name, point, own, routed)
            shared = {k: v for k, v in self.params.items() if k not in point or k in kept}
            kinds.append((planner, sampler, {**shared, **kept}))
        out: Dict[str, Cell] = {}  # by cell id, in order
        for world in self.worlds:
            for planner, sampler, settings in kinds:
                cell = Cell(world, planner, sampler, settings)
                out.setdefault(cell.cell_id, cell)
        return list(out.values())

    def swept(self, cell: Cell) -> Dict[str, Any]:
        """The swept values ``cell`` ran with (its row's ``swept``, which names its group in the report)."""
        return {k: cell.params[k] for k in sorted(self.grid) if k in cell.params}

    def _points(self) -> List[Dict[str, Any]]:
        keys = sorted(self.grid)
        return [dict(zip(keys, values)) for values in itertools.product(*(self.grid[k] for k in keys))]

    def _routings(self) -> Iterator[Tuple[Component, Optional[Component], Dict[str, Any], Dict[str, Any],
                                          Dict[str, Any]]]:
        """``(planner, sampler, point, own, routed)`` for each planner, each sampler it draws from and each grid
        point: its own settings (the planner's and the sampler's), and the settings it is given
        (:func:`routed_params`)."""
        for planner in self.planners:
            for sampler in self.samplers if samples(planner.name) else [None]:
                own = {**planner.params, **(sampler.params if sampler else {})}
                for point in self._points():
                    yield planner, sampler, point, own, routed_params(
                        planner.name, {**self.params, **point}, own, sampler.name if sampler else None)

    def routed_keys(self) -> set:
        """The shared and swept settings some planner (with some sampler) is given, whether or not its
        search then uses them (a weight beside astar with heuristic none, which a note names)."""
        return {k for _, _, point, _, routed in self._routings() for k in routed if k in self.params or k in point}

    def unswept(self) -> Dict[str, List[str]]:
        """Each planner's (and, where they differ, each sampler's) label with the swept settings none of its
        cells takes (so its cells run once for all their values), for a note; those that take every swept
        setting are left out. Settings it sets itself are :meth:`own_over_sweep`'s."""
        return self._not_split(own_ones=False)

    def own_over_sweep(self) -> Dict[str, List[str]]:
        """As :meth:`unswept`, for the swept settings a planner or its sampler sets itself, so its own value wins
        over every swept one (the note said it did not take them: attack, session 23)."""
        return self._not_split(own_ones=True)

    def partly_unswept(self) -> Dict[str, List[str]]:
        """Each planner's (and, where they differ, each sampler's) label with the swept settings some of its
        cells use and others do not, each as ``"weight where heuristic=none"``: the swept values of the cells
        that do not, by the settings that tell them apart (all of them when none does alone). astar under
        ``heuristic: [none, octile]`` and ``weight: [1, 5]`` searches unweighted with heuristic none, so the
        weight does not split those cells; a car-like tree under a swept ``motion`` takes ``turning_radius``
        only where it is dubins or reeds_shepp. For a note (newcomer, session 24: only settings that no cell
        uses were noted)."""
        usage = self._usage()

        def parts(key) -> List[str]:
            used, _, dropped = usage[key]
            return [f"{name} where {_where(points, self.grid, name)}"
                    for name, points in sorted(dropped.items()) if name in used]

        return self._by_label(parts)

    def _not_split(self, own_ones: bool) -> Dict[str, List[str]]:
        usage = self._usage()

        def keys(key) -> List[str]:
            used, own, _ = usage[key]
            unused = set(self.grid) - used
            return sorted(unused & own if own_ones else unused - own)

        return self._by_label(keys)

    def _usage(self) -> Dict[Tuple[int, int], Tuple[set, set, Dict[str, List[Dict[str, Any]]]]]:
        """By ``(id(planner), id(sampler))``: the swept settings some of its cells use (:func:`_taken`), those it
        sets itself, and each swept setting it is not given or does not use with the grid points where not."""
        out: Dict[Tuple[int, int], Tuple[set, set, Dict[str, List[Dict[str, Any]]]]] = {}
        for planner, sampler, point, own, routed in self._routings():
            used, _, dropped = out.setdefault((id(planner), id(sampler)), (set(), set(own), {}))
            taken = _taken(planner.name, point, own, routed)
            used.update(taken)
            for name in set(point) - set(taken) - set(own):
                dropped.setdefault(name, []).append(point)
        return out

    def _by_label(self, found) -> Dict[str, List[str]]:
        """``found((id(planner), id(sampler)))`` (a list, empty for none) by label: the planner's when it is the
        same for every sampler it draws from, else each sampler's (``"rrt with uniform"``)."""
        out = {}
        for planner in self.planners:
            samplers = self.samplers if samples(planner.name) else [None]
            each = [found((id(planner), id(sampler))) for sampler in samplers]
            if len({tuple(items) for items in each}) == 1:  # the same for every sampler: the planner's
                if each[0]:
                    out[planner.title] = each[0]
                continue
            for sampler, items in zip(samplers, each):
                if items:
                    out[f"{planner.title} with {sampler.title}"] = items
        return out

    def trial_specs(self) -> List[Dict[str, Any]]:
        """Everything a worker needs to run each trial (plain, picklable data),
        cell by cell. Trial 0 of each cell keeps its tree (the example plot)."""
        specs = []
        for cell in self.cells():
            for i in range(self.trials):
                specs.append(self._spec(cell, i))
        return specs

    def noise_specs(self) -> List[Dict[str, Any]]:
        """Repeats of the first :data:`NOISE_REPEATS` trials of each cell: the
        same seed, so the same work; how their times differ from the first
        run's measures the timing noise (see :mod:`navlab.bench.analysis`)."""
        return [self._spec(cell, i, repeat=1) for cell in self.cells() for i in range(min(NOISE_REPEATS, self.trials))]

    def _spec(self, cell: Cell, i: int, repeat: int = 0) -> Dict[str, Any]:
        cid = cell.cell_id
        spec = {"trial_id": f"{cid}-{i:04d}" + (f"-r{repeat}" if repeat else ""), "cell_id": cid,
                "cell": cell.to_dict(), "label": cell.label, "trial": i, "seed": trial_seed(self.seed, cid, i),
                "budget": dict(self.budget),
                "swept": self.swept(cell),
                "keep_tree": i == 0 and not repeat}
        if repeat:
            spec["repeat"] = repeat
        entry = self.maps.get(cell.world)
        if entry is not None:
            spec["map"] = {k: v for k, v in entry.items() if k != "queries"}
            spec["query"] = entry["queries"][i % len(entry["queries"])]
        return spec

    def to_dict(self) -> Dict[str, Any]:
        return {"name": self.name, "description": self.description,
                "worlds": [self.maps.get(w, w) for w in self.worlds],
                "planners": [p.to_dict() for p in self.planners], "samplers": [s.to_dict() for s in self.samplers],
                "params": dict(self.params), "grid": {k: list(v) for k, v in self.grid.items()},
                "budget": dict(self.budget), "trials": self.trials, "seed": self.seed,
                "claims": [dict(c) for c in self.claims], "study": dict(self.study)}

    def fingerprint(self) -> str:
        """Identity of the results this experiment produces. The trial count is
        left out: more trials extend a result set, they do not change it."""
        data = self._identity()
        # What no planner uses changes no result (:meth:`unused`): each is left as it is when not given (so the
        # runs made before keep their identity: review, session 23), and a run resumes without it (astar with
        # --sampler gaussian, then without, was refused "differs in: samplers"; --max-iter and --seed alike:
        # attacks and newcomer, sessions 22-23).
        unused = self.unused()
        if unused["samplers"]:
            data["samplers"] = [_component(s, "samplers").to_dict() for s in DEFAULT_SAMPLERS]
        data["budget"] = {k: v for k, v in data["budget"].items() if k not in unused["budget"]}
        if unused["seed"]:
            data["seed"] = DEFAULT_SEED
        return stable_hash(data)[:16]

    def unused(self) -> Dict[str, Any]:
        """What none of the experiment's planners uses: ``samplers`` (true when no tree planner draws them),
        ``budget`` (the fields no planner takes: every one beside grid and pose planners alone, ``max_iter``
        beside OMPL planners that count no iterations) and ``seed`` (true when no planner draws random
        numbers). The run's identity leaves them out, and ``navlab bench`` says so in a note."""
        from .ompl_planners import COUNTING

        trees = any(samples(p.name) for p in self.planners)
        ompl = [p.name[len(OMPL_PREFIX):] for p in self.planners if p.name.startswith(OMPL_PREFIX)]
        if trees:
            budget: List[str] = []
        elif not ompl:
            budget = sorted(self.budget)
        else:
            budget = ["max_iter"] if "max_iter" in self.budget and not any(n in COUNTING for n in ompl) else []
        return {"samplers": not trees, "budget": budget, "seed": not trees and not ompl}

    def fingerprints(self) -> Tuple[str, str]:
        """:meth:`fingerprint`, and the identity navlab gave the same experiment until session 23 (every
        setting, used or not), which a run made then recorded: either resumes it (a run of ompl:RRTConnect with
        a max_iter it never read could no longer be resumed: review, session 23)."""
        return self.fingerprint(), stable_hash(self._identity())[:16]

    def _identity(self) -> Dict[str, Any]:
        """:meth:`to_dict` without the fields that change no result (:data:`DESCRIPTIVE`)."""
        return {k: v for k, v in self.to_dict().items() if k not in DESCRIPTIVE}

    def world_contents(self) -> Dict[str, str]:
        """A digest of each world read from a file (a world file's bytes, a map's cells, resolution and
        origin), by world name: a file edited between a run and its resume left one cell holding costs of
        two worlds (attack, session 23), so a resume compares them (:mod:`navlab.bench.store`)."""
        from ..world.scenes import SCENES
        from .maps import load_grid

        out = {}
        for world in self.worlds:
            if world in self.maps:
                grid = load_grid(self.maps[world]["map"])
                out[world] = content_digest(np.packbits(grid.blocked).tobytes(), np.packbits(grid.unknown).tobytes(),
                                            repr((grid.blocked.shape, grid.resolution, tuple(grid.origin))).encode())
            elif world not in SCENES and Path(world).is_file():
                out[world] = content_digest(Path(world).read_bytes())
        return out


def _where(points: List[Dict[str, Any]], grid: Dict[str, list], name: str) -> str:
    """The grid ``points`` (the cells that do not use swept setting ``name``) as a condition on the other swept
    settings: on those whose values there are fewer than the grid's (``heuristic=none``, not also every
    ``connectivity``), or on all when none is so (``costmap=True or costmap=False and heuristic=none``)."""
    others = [k for k in sorted(grid) if k != name]
    telling = [k for k in others if len({repr(p[k]) for p in points}) < len(grid[k])] or others
    conditions = dict.fromkeys(" and ".join(f"{k}={p[k]}" for k in telling) for p in points)
    return " or ".join(conditions) or "-"


def _taken(planner: str, point: Dict[str, Any], own: Dict[str, Any], routed: Dict[str, Any]) -> Dict[str, Any]:
    """The swept values of ``point`` a cell of ``planner`` takes: those it is given (``routed``) and does not
    set itself (``own``), and a grid algorithm's search uses (:func:`~navlab.grid.planner.settings_ignored`:
    dijkstra ran once per swept weight, the same search each time; review, session 23)."""
    from ..grid.planner import GRID_ALGORITHMS, settings_ignored

    ignored = set(settings_ignored(planner, routed)) if planner in GRID_ALGORITHMS else set()
    return {k: v for k, v in point.items() if k in routed and k not in own and k not in ignored}


def content_digest(*parts: bytes) -> str:
    """A short digest of ``parts`` (a world's content), for :meth:`Experiment.world_contents`."""
    digest = hashlib.sha256()
    for part in parts:
        digest.update(part)
    return digest.hexdigest()[:16]


# -- reading and checking ----------------------------------------------------

def experiment_data(source: Union[str, Path]) -> Tuple[Dict[str, Any], str]:
    """The raw mapping of a YAML experiment file or a built-in suite, and how
    to name it in messages (a file's name defaults to its stem; relative
    world paths in a file are made relative to the file's folder)."""
    from .suites import find_suite, suite_names

    if Path(source).exists():
        where = str(source)
        data = read_yaml(source, ExperimentError, MAX_FILE_BYTES, what="experiment file")
        if isinstance(data, dict):
            data.setdefault("name", Path(source).stem)
            if isinstance(data.get("worlds"), (list, str, dict)):
                try:
                    worlds = _as_list(data["worlds"], "worlds")
                except ExperimentError as exc:  # name the file ("'worlds' is empty" named nothing)
                    raise ExperimentError(f"{where}: {exc}") from None
                data["worlds"] = [_beside(w, Path(source).parent) for w in worlds]
        return data, where
    if isinstance(source, str):
        found = find_suite(source)
        if found is not None:
            return found(), f"suite '{source}'"
    from .suites import BARN_SUITE

    names = suite_names() + [BARN_SUITE[0]]  # barn runs navigators, not an experiment file, but is a suite to a user
    raise ExperimentError(f"no experiment file or suite named '{source}'; suites: "
                          f"{', '.join(names)}." + suggest(str(source), names))


def _beside(world: Any, folder: Path) -> Any:
    """A relative world path of an experiment file, read from the file's folder
    (scene names and absolute paths unchanged)."""
    from ..world.scenes import SCENES

    if isinstance(world, dict):  # a map world: its map and scenario files
        return {k: (str(folder / v) if k in ("map", "scen") and isinstance(v, str) and not Path(v).is_absolute()
                    else v) for k, v in world.items()}
    if not isinstance(world, str) or world in SCENES or Path(world).is_absolute():
        return world
    if Path(world).suffix.lower() not in (".yaml", ".yml", ".map", ".scen", ".pgm", ".png") and "/" not in world:
        return world  # not a path: let the world loader name it ("did you mean")
    return str(folder / world)


def load_experiment(source: Union[str, Path, Dict[str, Any]], where: Optional[str] = "experiment") -> Experiment:
    """Read an experiment from a YAML file, a built-in suite name or a mapping,
    and check every name and parameter before anything runs. Its errors open with
    ``where`` (a file's or suite's own name for those), or, with ``where=None`` and a
    mapping, with nothing (``navlab bench``'s flags: said as any command's errors are)."""
    data = source
    if not isinstance(source, (dict, str, os.PathLike)):  # (5, None, a list: a TypeError from pathlib: API attack)
        raise ExperimentError(_at(where, "expected a YAML file's path, a suite name or a mapping, got "
                                         f"{type(source).__name__}"))
    if not isinstance(source, dict):
        data, where = experiment_data(source)
    if not isinstance(data, dict):
        raise ExperimentError(_at(where, f"expected a mapping with fields {', '.join(FIELDS)}"))
    try:
        exp = _from_dict(data)
        validate(exp)
    except ValueError as exc:  # ExperimentError, and unknown names/parameters from the registries
        raise ExperimentError(_at(where, str(exc))) from None
    return exp


def _at(where: Optional[str], message: str) -> str:
    return message if where is None else f"{where}: {message}"


def check_plain(value: Any, path: str = "") -> None:
    """Refuse what YAML can hold but an experiment cannot: a key that is not a name (``{1: [2]}``), and
    binary data, dates and sets (``!!binary``, ``2001-01-01``, ``!!set``), which reached a trial or the
    results file as internal errors (an attack on the command, session 17). ``path`` names the place."""
    if isinstance(value, dict):
        for key, item in value.items():
            if not isinstance(key, str):
                raise ExperimentError(f"{path + ': ' if path else ''}keys must be names, got {shown(key)}")
            check_plain(item, f"{path}.{key}" if path else key)
    elif isinstance(value, (list, tuple)):
        for i, item in enumerate(value):
            check_plain(item, f"{path}[{i}]")
    elif isinstance(value, float) and not math.isfinite(value):  # (experiment.json held a bare NaN: attack, s. 25)
        raise ExperimentError(f"{path}: numbers must be finite, got {shown(value)}")
    elif value is not None and not isinstance(value, (str, bool, int, float)):
        kind = {"bytes": "binary data", "date": "a date", "datetime": "a date and time", "set": "a set"}.get(
            type(value).__name__, f"a {type(value).__name__}")
        got = value_text(value) if isinstance(value, datetime.date) else shown(value)
        raise ExperimentError(f"{path}: {kind} is not an experiment value (names, numbers, true/false, lists "
                              f"and mappings are), got {got}")


def _from_dict(data: Dict[str, Any]) -> Experiment:
    # numpy's scalars as Python's: a mapping from Python takes what navlab.plan takes (load_experiment refused
    # np.True_ as "a bool is not an experiment value": attack, session 25)
    data = plain_values(data)
    check_plain(data)
    if not set(data) & {"worlds", "planners"}:
        # a world or map file given where an experiment goes (`navlab bench my_world.yaml`: newcomer, session 29)
        world_keys = [key for key in ("bounds", "obstacles", "robot_radius") if key in data]
        if {"image", "resolution"} <= set(data):
            raise ExperimentError("this is a map file ('image' and 'resolution'), not an experiment: benchmark it "
                                  "with --world FILE --start X Y --goal X Y --planner NAME")
        if world_keys:
            raise ExperimentError(f"this is a world file ({listed(repr(k) for k in world_keys[:2])}), not an "
                                  "experiment: benchmark it with --world FILE --planner NAME")
    for key in data:
        if key not in FIELDS:
            raise ExperimentError(f"unknown field '{key}'; valid: {', '.join(FIELDS)}." + suggest(key, list(FIELDS)))
    for key in ("worlds", "planners"):
        if key not in data:
            raise ExperimentError(f"missing field '{key}'")
    if not isinstance(data.get("budget") or {}, dict):
        raise ExperimentError(f"'budget' must be a mapping (max_iter, max_time), got {data['budget']!r}")
    budget = dict(data.get("budget") or {})
    for key in budget:
        if key not in BUDGET_FIELDS:
            raise ExperimentError(f"unknown budget field '{key}'; valid: {', '.join(BUDGET_FIELDS)}."
                                  + suggest(key, list(BUDGET_FIELDS)))
    grid = data.get("grid") or {}
    if not isinstance(grid, dict):
        raise ExperimentError("'grid' must map parameter names to lists of values")
    grid = {k: (list(v) if isinstance(v, (list, tuple)) else [v]) for k, v in grid.items()}
    study = data.get("study") or {}
    if not isinstance(study, dict):
        raise ExperimentError("'study' must be a mapping (title, measured, table)")
    for key in ("short", "title", "measured"):  # they are the report's sentences
        if not isinstance(study.get(key, ""), str):
            raise ExperimentError(f"study.{key} must be text, got {study[key]!r}")
    from .maps import is_map_entry, map_entry

    worlds, maps = [], {}
    for entry in _as_list(data["worlds"], "worlds"):
        if is_map_entry(entry):
            checked = map_entry(entry)
            if checked["name"] in maps:
                raise ExperimentError(f"two map worlds are named '{checked['name']}'; give them distinct 'name's")
            maps[checked["name"]] = checked
            worlds.append(checked["name"])
        elif isinstance(entry, str):
            worlds.append(entry)
        else:  # (5 was looked up as the scene '5': API attack, session 29)
            raise ExperimentError(f"each of 'worlds' is a scene name, a world or map file, or a mapping with 'map', "
                                  f"'start' and 'goal', got {shown(entry)}")
    return Experiment(
        samplers_given=data.get("samplers") is not None,
        study=dict(study),
        name=_plain_name(data.get("name", "experiment")),
        description=str(data.get("description", "")),
        worlds=worlds,
        maps=maps,
        planners=[_component(p, "planners") for p in _as_list(data["planners"], "planners")],
        samplers=[_component(s, "samplers")
                  for s in _as_list(data.get("samplers", list(DEFAULT_SAMPLERS)), "samplers")],
        params=_mapping(data.get("params"), "params"),
        grid=grid,
        budget={k: v for k, v in budget.items() if v is not None},
        # (null: not given, as for the budget's fields; it was "must be a positive integer, got None")
        trials=20 if data.get("trials") is None else data["trials"],
        seed=DEFAULT_SEED if data.get("seed") is None else data["seed"],
        claims=[_claim(c) for c in _claims_list(data.get("claims"))],
    )


def _plain_name(name: Any) -> str:
    """An experiment name names its output folder: a plain file name only."""
    text = str(name)
    if not text or text in (".", "..") or any(c in text for c in "/\\\0") or text != text.strip():
        raise ExperimentError(f"'name' must be a plain file name (no path separators, not '.' or '..'), "
                              f"got {text!r}")
    return text


def routed_params(planner: str, shared: Dict[str, Any], own: Dict[str, Any], sampler: Optional[str] = None
                  ) -> Dict[str, Any]:
    """A cell's settings: the experiment's shared ``params`` and ``grid``
    values that apply to this kind of planner (grid settings to grid
    algorithms, the others to tree and OMPL planners), then its own. A tree planner's cell with
    ``sampler`` takes that sampler's settings only (None: any sampler's)."""
    from ..pose_queries import HYBRID_PARAMS, POSE_PLANNERS
    from ..queries import GRID_PARAMS
    from ..setting_names import COSTMAP_PARAMS, HYBRID_ONLY

    if planner in POSE_PLANNERS:  # its own settings (motion, turning_radius, ...)
        return {**{k: v for k, v in shared.items() if k in HYBRID_PARAMS}, **own}
    if planner.startswith(OMPL_PREFIX):  # (it took Hybrid A*'s turning_radius too, and refused it: review,
        from .ompl_planners import ompl_params  # session 22)

        takes = set(ompl_params(planner[len(OMPL_PREFIX):]))
        return {**{k: v for k, v in shared.items() if k in takes}, **own}
    if not samples(planner):  # a grid algorithm; astar on a costmap takes the costmap's settings instead
        if planner == "astar" and {**shared, **own}.get("costmap") is True:
            takes: Tuple[str, ...] = COSTMAP_PARAMS
        else:  # (astar takes any costmap value, to be checked: costmap=yes was "applies to none": attack, s. 23)
            takes = GRID_PARAMS + (("costmap",) if planner == "astar" else ())
        return {**{k: v for k, v in shared.items() if k in takes and k not in HYBRID_ONLY}, **own}
    car = {**shared, **own}.get("motion") in ("dubins", "reeds_shepp")

    def takes(key: str) -> bool:
        """Whether a tree planner, car-like (``car``) or not, takes the shared setting ``key``: a car-like
        one plans on a raster (resolution) with a turning radius, footprint and heading bins, and ends
        exactly at the goal pose; any takes the query's allow_unknown (review and attack, session 22: these
        went by kind of planner alone, so beside astar a car-like tree lost the resolution, and beside
        hybrid_astar a holonomic tree was given its turning_radius, and refused it)."""
        if key in HYBRID_ONLY:  # (Hybrid A*'s alone: beside rrt_star, distance_table went to the tree too)
            return False
        if key == "allow_unknown":
            return True
        if key in ("resolution", "turning_radius", "footprint", "heading_bins"):
            return car
        if key == "goal_tolerance":
            return not car
        return key in _tree_settings(planner, car, sampler)

    return {**{k: v for k, v in shared.items() if takes(k)}, **own}


@functools.lru_cache(maxsize=None)
def _tree_settings(planner: str, car: bool, sampler: Optional[str] = None) -> frozenset:
    """The settings tree planner ``planner`` takes, car-like (``car``) or not: its own, and those of
    ``sampler`` (None: of every sampler), and ``goal_sample_rate``, which any sampler takes (it wraps it in goal
    bias). A shared setting went to every tree planner, so ``params: {connect_circle_dist: 30}`` beside rrt_star
    refused rrt, which does not rewire (newcomer, session 23: docs/bench.md's own example), and
    ``grid: {sigma: [0.5, 1]}`` refused the uniform sampler's cells."""
    from ..registry import parameters_of
    from ..sampling.planners import PLANNERS
    from ..sampling.samplers import SAMPLERS
    from ..sampling.se2_planners import se2_tree_params

    if car:
        own = set(se2_tree_params(planner))
    else:
        own = set(parameters_of(PLANNERS.get(planner))) - {"sampler"}
    drawn = {key for name in ([sampler] if sampler else SAMPLERS.names())
             for key in parameters_of(SAMPLERS.get(name))} - {"base"}
    return frozenset(own | drawn | {"goal_sample_rate", "motion"})


def _check_world(world: str):
    """The world ``world`` names, loaded (or the experiment refused naming it)."""
    from ..world.sources import MissingQueryError, load_source

    try:
        return load_source(world)
    except MissingQueryError:
        raise ExperimentError(f"world '{world}' is a map, which has no start or goal: give it as "
                              f"{{map: {world}, scen: FILE.scen, queries: N}} or "
                              f"{{map: {world}, queries: [[start x, start y, goal x, goal y]]}}") from None


def _claim(entry: Any) -> Dict[str, Any]:
    if not isinstance(entry, dict) or set(entry) - set(CLAIM_FIELDS) or not {"text", "lower", "higher"} <= set(entry):
        raise ExperimentError(f"each claim is a mapping with {', '.join(CLAIM_FIELDS)}, got {entry!r}")
    # a sentence, and a group name (or a list of them) on each side ({a: 1} was an internal error)
    if not isinstance(entry["text"], str):
        raise ExperimentError(f"claim text must be text, got {entry['text']!r}")
    for key in ("lower", "higher"):
        names = entry[key] if isinstance(entry[key], list) else [entry[key]]
        if not names or not all(isinstance(n, str) for n in names):
            raise ExperimentError(f"claim {key} must be a group name or a list of them, got {entry[key]!r}")
    if entry.get("metric", "cost") not in CLAIM_METRICS:
        raise ExperimentError(f"claim metric must be one of {', '.join(CLAIM_METRICS)}, got {entry['metric']!r}")
    return {"metric": "cost", **entry}


def _claims_list(value: Any) -> list:
    """The experiment's claims: a list (of mappings, :func:`_claim`), or none (claims: 5 was a TypeError:
    API attack, session 29)."""
    if value is None:
        return []
    if not isinstance(value, list):
        raise ExperimentError(f"'claims' must be a list of claims, got {shown(value)}")
    return value


def _as_list(value: Any, what: str) -> list:
    items = value if isinstance(value, list) else [value]
    if not items or value is None:
        raise ExperimentError(f"'{what}' is empty: nothing to run")
    if any(v is None for v in items):  # ("- " with nothing after it in YAML)
        raise ExperimentError(f"'{what}' has an empty entry (null): give each a name")
    return items


def _component(entry: Any, what: str) -> Component:
    if isinstance(entry, str):
        return Component(entry)
    if isinstance(entry, dict) and "name" in entry:
        params = {k: v for k, v in entry.items() if k not in ("name", "label")}
        label = entry.get("label", "")
        if "label" in entry and (isinstance(label, bool) or not isinstance(label, (str, int, float))
                                 or not str(label).strip()):
            # ('' read as no label, and null as the label 'None': session 23's newcomer)
            raise ExperimentError(f"'{what}': the label of {entry['name']!r} must be a non-empty text, got "
                                  f"{shown(label)}")
        return Component(str(entry["name"]), params, str(label))
    raise ExperimentError(f"each of '{what}' is a name or a mapping with 'name' (and settings), got {entry!r}")


def _mapping(value: Any, field: str) -> Dict[str, Any]:
    """A field that must be a mapping (``params: [1]`` is refused naming it)."""
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise ExperimentError(f"'{field}' must be a mapping of name: value, got {value!r}")
    return dict(value)


def validate(exp: Experiment) -> None:
    """Check names, counts and parameters by building each cell's parts once."""
    from ..pose_queries import POSE_PLANNERS
    from ..queries import is_grid_planner

    for planner in exp.planners:
        if not planner.name.startswith(OMPL_PREFIX):
            if planner.name not in POSE_PLANNERS:
                is_grid_planner(planner.name)  # unknown names: "did you mean", both kinds listed

    exp.trials = check_trials(exp.trials)
    # Counted before the cells are built: a grid of 8 parameters × 10 values is 10⁸ cells.
    cells = len(exp.worlds) * len(exp.planners) * max(len(exp.samplers), 1) * math.prod(
        len(v) for v in exp.grid.values())
    if cells > MAX_CELLS:
        raise ExperimentError(f"the experiment has {cells:.3g} cells (worlds × planners × samplers × grid values), "
                              f"more than the {MAX_CELLS} a run supports; sweep fewer values")
    if cells * exp.trials > MAX_TRIALS:
        raise ExperimentError(f"'trials': {shown(exp.trials)} trials in each of {cells} cells is "
                              f"{_roughly(cells * exp.trials)} trials, more than the {MAX_TRIALS:.0e} a run supports")
    exp.seed = check_seed(exp.seed)
    for key, values in exp.grid.items():
        if not values:
            raise ExperimentError(f"grid parameter '{key}' has no values: the grid is empty")
    if exp.budget.get("max_iter") is not None:
        exp.budget["max_iter"] = check_max_iter(exp.budget["max_iter"])
    if exp.budget.get("max_time") is not None:
        check_max_time(exp.budget["max_time"])
    labels = [p.title for p in exp.planners]
    if len(set(labels)) != len(labels) or len({s.title for s in exp.samplers}) != len(exp.samplers):
        sampler_labels = [x.title for x in exp.samplers]
        shared = sorted({t for t in labels if labels.count(t) > 1} | {
            t for t in sampler_labels if sampler_labels.count(t) > 1})
        raise ExperimentError(f"two planners or two samplers share the label {', '.join(map(repr, shared))}; give "
                              "them distinct 'label's")
    for part in [*exp.planners, *exp.samplers]:  # (" / " parts a group's label: a claim then failed, after
        if " / " in part.title or part.title == "-":  # every trial, with an internal error; attack, session 23)
            raise ExperimentError(f"label {part.title!r}: a label may not hold ' / ' or be '-', which the report's "
                                  "group names are made of")
    worlds: Dict[str, Any] = {}  # each world loaded once (its pose queries' defaults come from it)
    for world in exp.worlds:
        if world not in exp.maps:
            worlds[world] = _check_world(world)
    used = exp.routed_keys()  # the shared settings some cell's planner is given (used by its search or not)
    for cell in exp.cells():
        try:
            _check_cell(exp, cell, worlds)
        except ValueError as exc:
            blamed = _refused_where(exp, cell, str(exc))
            if not blamed:
                raise
            raise ExperimentError(f"{blamed}: {exc}") from None
    _check_swept_grid_values(exp)
    _check_shared_params_used(exp, used)
    _check_unique_cells(exp)
    _check_claim_groups(exp)


def _refused_where(exp: Experiment, cell: Cell, message: str) -> str:
    """Where a refusal of ``cell`` came from: a swept value ("grid: planner 'jps' where connectivity=4"), or a
    setting of the planner's or the sampler's own entry ("planner 'b'", by its label), or '' (the refusal then
    reads as it did: the setting is shared or the budget's). A setting is blamed when the message names it;
    one a planner or sampler sets itself is its entry's, not the sweep's. Until session 25 a bad swept value
    read as the planner's own setting ("motion: ..."), and of two labelled astar entries the refusal did not
    say which (attack); a first version named every swept value of the cell, whatever the refusal was about
    (review, session 25)."""
    said = re.split(r"[;.,]? valid:|Did you mean", message)[0]  # (not the names a refusal lists as valid)

    def names(keys) -> List[str]:
        return [k for k in keys if re.search(rf"\b{re.escape(k)}\b", said)]

    # a swept value the message names is the cell's own cause (rrt's own turning_radius is refused because the
    # sweep made this cell holonomic: second review, session 25); else an entry's own setting it names
    own = {**cell.planner.params, **(cell.sampler.params if cell.sampler else {})}
    swept = exp.swept(cell)
    named = [k for k in names(swept) if k not in own]
    if not named:
        if cell.sampler is not None and names(cell.sampler.params):
            return f"sampler '{cell.sampler.title}' of planner '{cell.planner.title}'"
        return f"planner '{cell.planner.title}'" if names(cell.planner.params) else ""
    from ..queries import take_sampler_params

    samplers = cell.sampler is not None and take_sampler_params(cell.sampler.name, dict.fromkeys(named))
    part = f"sampler '{cell.sampler.title}' of planner '{cell.planner.title}'" if samplers else \
        f"planner '{cell.planner.title}'"
    return f"grid: {part} where " + " and ".join(f"{k}={_as_swept(swept[k])}" for k in named)


def _as_swept(value: Any) -> str:
    """A swept value as the report's groups write it (``motion=holonomic``), but text that reads as a number
    quoted: "connectivity=8: connectivity must be 4 or 8, got '8'" said 8 twice (newcomer, session 25)."""
    if isinstance(value, str):
        try:
            float(value)
        except ValueError:
            return value
        return repr(value)
    return str(value)


def _check_swept_grid_values(exp: Experiment) -> None:
    """Refuse a bad value of a grid search's setting in ``grid:`` that no cell uses (``weight: [1, 0.5]`` beside
    dijkstra ran, noted as unused; a cell that uses it is checked with its planner): by the grid planners' rule,
    as the same value in ``params:`` is."""
    from ..grid.settings import check_grid_settings
    from ..setting_names import GRID_PARAMS

    for key, values in exp.grid.items():
        if key in GRID_PARAMS:
            for value in values:
                try:
                    check_grid_settings({key: value})
                except ValueError as exc:
                    raise ExperimentError(f"grid: {key}={value}: {exc}") from None


def _check_cell(exp: Experiment, cell: Cell, worlds: Dict[str, Any]) -> None:
    """Check one cell's planner, sampler and settings as its trials will build them (``worlds``: the scenes
    and world files loaded once, by name)."""
    from ..pose_queries import POSE_PLANNERS, check_pose_query, is_pose_query
    from ..queries import (build_sampler, check_costmap_settings, check_tree_allow_unknown, split_grid_params,
                           split_params, take_query_params, take_sampler_params)
    from ..sampling.planners import make_planner
    from .ompl_planners import check_ompl_name, check_ompl_query, ompl_available

    # (with its own settings: a car-like tree's own motion decides what it takes of the shared ones)
    own = routed_params(cell.planner.name, cell.params, cell.planner.params,
                        cell.sampler.name if cell.sampler else None)
    if cell.planner.name in POSE_PLANNERS:
        _check_pose_params(cell.planner.name, cell.planner.params)
    if cell.planner.name.startswith(OMPL_PREFIX):
        check_ompl_name(cell.planner.name[len(OMPL_PREFIX):])
        if not ompl_available():
            from ..extras import install_command

            raise ExperimentError(f"planner '{cell.planner.name}' needs OMPL, which is not installed: "
                                  f"{install_command('ompl')}")
        check_ompl_query(cell.planner.name[len(OMPL_PREFIX):], own, exp.budget)
        return
    if cell.world in exp.maps and own.get("resolution") is not None:
        # (every trial was an ERROR row, docs/bench.md's own maps example among them: review and attack,
        # session 22)
        raise ExperimentError(f"resolution: world '{cell.world}' is a map, planned on its own cells; "
                              "leave resolution out")
    if is_pose_query(cell.planner.name, own):  # (a bad motion named)
        # its settings refused now, not by every trial as a run of ERROR rows (attack, session 22: exact_retry:
        # [yes], heading_bins: [3]); a map world's settings alone (review, session 22), its map read by the trials
        if own.get("goal_tolerance") not in (None, 0, 0.0):  # (as navlab.plan refuses it)
            raise ExperimentError(f"goal_tolerance: {cell.planner.name} between poses ends exactly at the goal "
                                  "pose; leave goal_tolerance out")
        settings = {k: v for k, v in own.items() if k != "goal_tolerance"}
        if cell.sampler is not None:  # a car-like tree's sampler, as its query builds it (attack, session 22)
            build_sampler(cell.sampler.name, {**take_sampler_params(cell.sampler.name, settings),
                                              **cell.sampler.params})
        check_pose_query(worlds.get(cell.world), cell.planner.name, settings,
                         cell.sampler.name if cell.sampler else "")
        _check_raster(worlds.get(cell.world), own)
        _check_turning_scale(worlds.get(cell.world), cell.world, own, exp.maps.get(cell.world))
        return
    if cell.sampler is None and "costmap" in own and own["costmap"] is not False:  # as navlab.plan takes it
        check_flag("costmap", own["costmap"])  # (0 passed as false, then every trial refused it: review, session 23)
        world = worlds.get(cell.world)
        # a map world's robot, from its entry (its map is read by the trials: review and attack, session 23)
        radius = exp.maps[cell.world].get("robot_radius", 0.0) if cell.world in exp.maps else world.robot_radius
        check_costmap_settings(cell.planner.name, {k: v for k, v in own.items() if k != "costmap"}, radius)
        _check_raster(world, own)
        return
    if cell.sampler is None:  # a grid algorithm: its settings only, no budget
        split_grid_params(cell.planner.name, {k: v for k, v in own.items() if k != "costmap"})
        _check_raster(worlds.get(cell.world), own)
        return
    params = {**own, **cell.sampler.params, **exp.budget}
    # the query's own settings (goal_tolerance, allow_unknown, motion=holonomic), as navlab.plan takes them
    # (goal_tolerance was refused here, "Did you mean 'goal_tolerance'?", though each trial takes it:
    # review, session 22)
    _, allow_unknown = take_query_params(params, grid=False)
    if cell.world not in exp.maps:
        check_tree_allow_unknown(worlds[cell.world], allow_unknown)
    to_planner, to_sampler = split_params(cell.planner.name, cell.sampler.name, params)
    planner = make_planner(cell.planner.name, sampler=build_sampler(cell.sampler.name, to_sampler), **to_planner)
    try:
        planner.check_fits()  # a budget no trial could run: refused now, not as a run of ERROR rows
    except ValueError as exc:
        raise ExperimentError(f"budget: {exc}") from None


def _check_raster(world, settings: Dict[str, Any]) -> None:
    """Refuse a ``resolution`` that rasterises ``world`` (a geometric world; None: none to check) to more
    cells than navlab holds, or to none: each trial refused it, an ERROR row (attack, session 22)."""
    from ..grid.rasterize import grid_shape

    if world is not None and world.occupancy is None and settings.get("resolution") is not None:
        grid_shape(world.bounds, settings["resolution"])


def _check_turning_scale(world, name: str, settings: Dict[str, Any], map_entry: Optional[Dict[str, Any]] = None
                         ) -> None:
    """Refuse a turning radius whose one heading step of arc is longer than the world is across, which
    every trial refused, an ERROR row (attack, session 22: 300 m on trap). ``world`` is a geometric world,
    measured on its bounds, which its raster lies within, so what is refused here would be refused by each
    trial too; or ``map_entry`` a map world's (:func:`~navlab.bench.maps.map_entry`), measured on its cells
    as each trial measures them (its map is read once, by the experiment's check of its queries)."""
    from ..sampling.footprint_lattice import check_heading_step
    from .maps import load_grid

    if settings.get("turning_radius") is None:
        return
    if map_entry is not None:
        grid = load_grid(map_entry["map"])
        extent = math.hypot(grid.width, grid.height) * grid.resolution
    elif world is not None and world.occupancy is None:
        extent = math.hypot(world.bounds.xmax - world.bounds.xmin, world.bounds.ymax - world.bounds.ymin)
    else:
        return
    check_heading_step(float(settings["turning_radius"]), int(settings.get("heading_bins", 72)), extent,
                       f"world '{name}'")


def _check_pose_params(planner: str, params: Dict[str, Any]) -> None:
    """A heading-aware planner's own settings are its, or the experiment is refused (with a did-you-mean)."""
    from ..setting_names import HYBRID_PARAMS, setting_hint

    for key in params:
        if key not in HYBRID_PARAMS:
            raise ExperimentError(f"unknown parameter '{key}' for planner '{planner}'; valid: "
                                  f"{', '.join(HYBRID_PARAMS)}." + setting_hint(key, planner, HYBRID_PARAMS))


def _check_shared_params_used(exp: Experiment, used: set) -> None:
    """Refuse a shared setting (``params``, ``grid``, ``--param``) that none of the
    experiment's planners takes: routed to no planner, a typo (``heuristc``,
    ``heading_binz``) would otherwise run every trial on the defaults."""
    from ..pose_queries import HYBRID_PARAMS
    from ..queries import GRID_PARAMS
    from ..setting_names import taken_elsewhere

    shared = set(exp.params) | set(exp.grid)
    for key in sorted(shared - used):
        planners = sorted({p.name for p in exp.planners})
        names = ", ".join(planners)
        # who does take it, rather than the nearest name: that was 'turning_radius' itself (newcomer, session 22)
        trees = {k for p in exp.planners if samples(p.name)
                 for car in (False, True) for k in _tree_settings(p.name, car)}
        hint = taken_elsewhere(key, planners[0], own=f"planner{'s' if len(planners) > 1 else ''} {names}") or \
            suggest(key, sorted(used | set(GRID_PARAMS) | set(HYBRID_PARAMS) | trees))
        if key == "goal_tolerance":  # (the query's, which only planners for a point robot take)
            hint = (" A goal tolerance is for planners of a point robot: one between poses ends exactly at the "
                    "goal pose.")
        if key == "base":  # (goal bias's base sampler is no shared setting: "not of planner rrt" beside a
            # goal_bias sampler read as a contradiction: attack, session 25)
            hint = (" The goal_bias sampler's base sampler is set on the sampler itself, not shared: samplers: "
                    "[{name: goal_bias, base: gaussian}].")
        raise ExperimentError(f"parameter '{key}' applies to none of this experiment's planners ({names})." + hint)


def _check_unique_cells(exp: Experiment) -> None:
    """Refuse an experiment naming the same cell twice (``worlds: [trap, trap]``,
    ``grid: {expand_dis: [1, 1]}``): its trials would share trial ids and count twice. (Cells that come out
    the same by routing, a sweep a planner does not take, are one cell: :meth:`Experiment.cells`.)"""
    for what, values in (("worlds", exp.worlds), ("planners", [p.title for p in exp.planners]),
                         ("samplers", [s.title for s in exp.samplers])):
        twice = sorted({v for v in values if values.count(v) > 1})
        if twice:
            raise ExperimentError(f"'{what}' names {', '.join(map(repr, twice))} twice: each cell runs once "
                                  f"(use 'trials' for more runs)")
    for key, values in exp.grid.items():
        hashes = [stable_hash(_as_written_alike(v)) for v in values]
        for v, h in zip(values, hashes):
            if hashes.count(h) > 1:
                raise ExperimentError(f"grid '{key}' lists {v!r} twice: each cell runs once (use 'trials' for "
                                      f"more runs)")


def differences(a: Dict[str, Any], b: Dict[str, Any], ignored=DESCRIPTIVE,
                labels: Tuple[str, str] = ("there", "now")) -> List[str]:
    """Each field two experiments (:meth:`Experiment.to_dict`) differ in, with both values, a mapping's
    fields one by one: ``budget.max_iter 200 there, 5000 now`` ("differs in: budget" left the user to find
    which; newcomer run, session 21).

    Parameters
    ----------
    a, b : dict
        The experiments.
    ignored : sequence of str
        Fields not compared (by default those that do not change a result set, :data:`DESCRIPTIVE`).
    labels : (str, str)
        What ``a``'s and ``b``'s values are called.

    Returns
    -------
    list of str
        One entry per differing field, in the fields' order (per item and field for a list of map worlds).
    """
    out = []
    for key in sorted(set(a) | set(b)):
        old, new = a.get(key), b.get(key)
        if key in ignored or old == new:
            continue
        if _mappings(old) and _mappings(new) and len(old) == len(new):
            # a list of map worlds, item by item and field by field: whole, both sides were cut to the same
            # first characters and the change could not be seen (attack and newcomer, session 23)
            out += [line for i, (was, now) in enumerate(zip(old, new)) if was != now
                    for line in _fields_differing(f"{key}[{i}]", was, now, labels)]
        elif _mappings(old) and _mappings(new):  # (more or fewer planners or worlds: by their names)
            out.append(f"{key} {shown(_item_names(old))} {labels[0]}, {shown(_item_names(new))} {labels[1]}")
        else:
            out += _fields_differing(key, old, new, labels)
    return out


def _mappings(value: Any) -> bool:
    """Whether ``value`` is a list holding a mapping (a map world)."""
    return isinstance(value, list) and any(isinstance(item, dict) for item in value)


def _item_names(items: List[Any]) -> List[Any]:
    """A list's items by name: a mapping's ``label`` or ``name`` (a planner, a map world), else itself."""
    return [item.get("label") or item.get("name", item) if isinstance(item, dict) else item for item in items]


def _fields_differing(key: str, old: Any, new: Any, labels: Tuple[str, str]) -> List[str]:
    """``key``'s differing fields when both are mappings (``budget.max_iter 200 there, 5000 now``), else
    ``key`` whole."""
    if not (isinstance(old, dict) and isinstance(new, dict)):
        return [f"{key} {_set_or_not(old)} {labels[0]}, {_set_or_not(new)} {labels[1]}"]
    return [f"{key}.{sub} {_set_or_not(old.get(sub))} {labels[0]}, {_set_or_not(new.get(sub))} {labels[1]}"
            for sub in sorted(set(old) | set(new), key=str) if old.get(sub) != new.get(sub)]


def _set_or_not(value: Any) -> str:
    return "(not set)" if value is None else shown(value)


def _roughly(count: int) -> str:
    """A count in three digits (``1.2e+09``), or its digits when past a float (a 400-digit ``trials`` made
    the message itself fail: attack, session 20)."""
    return f"{count:.3g}" if count.bit_length() <= 1000 else f"a number of {digit_count(count)} digits"


# The count fields' checks, each returning the value as validate() keeps it; the command line's
# --trials, --seed, --max-iter and --max-time run them on a file's value before replacing it.
# A whole number written as a float (trials: 1e1, a number to YAML 1.2) is that integer, as --trials 1e1 is.
def _whole_count(value: Any, what: str, low: int, high: Optional[int]) -> int:
    """``value`` as a whole number from ``low`` to ``high`` (None: no bound; a whole float as its int), else
    ExperimentError naming ``what``."""
    value = _whole(value)
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        kind = "a positive integer" if low == 1 else "a non-negative integer"
        raise ExperimentError(f"{what} must be {kind}, got {shown(value)}")
    if high is not None and value > high:
        raise ExperimentError(f"{what} must be at most {high}, got {shown(value)}")
    return value


def check_trials(value: Any) -> int:
    """``trials``: a positive integer, at most :data:`MAX_TRIALS` (in all cells together, :func:`validate`)."""
    value = _whole_count(value, "'trials'", 1, None)
    if value > MAX_TRIALS:
        raise ExperimentError(f"'trials' must be at most {MAX_TRIALS} (what a run supports), got {shown(value)}")
    return value


def check_seed(value: Any) -> int:
    """``seed``: a non-negative integer that numpy's generators and navlab's counts take (as ``--seed``)."""
    return _whole_count(value, "'seed'", 0, MAX_COUNT)


def check_max_iter(value: Any) -> int:
    """``budget: {max_iter}``: a positive integer navlab's compiled loops can count to (as ``--max-iter``)."""
    return _whole_count(value, "budget max_iter", 1, MAX_COUNT)


def check_max_time(value: Any) -> float:
    """``budget: {max_time}``: a positive finite number [s]."""
    if not is_finite_real(value) or not value > 0:
        raise ExperimentError(f"budget max_time must be a positive finite number [s], got {shown(value)}")
    return value


def _whole(value: Any) -> Any:
    """A float that is a whole number as that int (``1e1`` → 10), anything else as it is (the checks name it;
    past 2⁶³ no count is meant, and the float reads better in their messages than 300 digits)."""
    if isinstance(value, float) and value.is_integer() and abs(value) < 2.0 ** 63:
        return int(value)
    return value


def _as_written_alike(value: Any) -> Any:
    """A number as the same float however written (weight 1 and 1.0 ran two identical cells: newcomer run,
    session 20); an integer no float equals, and anything else, as it is."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return value
    try:
        return float(value) if float(value) == value else value
    except OverflowError:  # (an integer past the largest float)
        return value


def _check_claim_groups(exp: Experiment) -> None:
    """Every name a claim compares must name a group of the experiment: a planner, a sampler, a swept
    ``key=value``, or a whole group label (as the report's tables write it); the two sides must differ and
    name each group once, and no two claims may share a text (a label typo in a whole group label, "-", a
    side named twice or a claim against itself passed, then had no verdict or two: attack, session 23)."""
    from .analysis import group_of

    names = {p.title for p in exp.planners} | {s.title for s in exp.samplers}
    names |= {f"{k}={v}" for k, values in exp.grid.items() for v in values}
    labels = {group_of({"planner": c.planner.title, "sampler": c.sampler.title if c.sampler else "-",
                        "swept": exp.swept(c)}) for c in exp.cells()}
    texts = [claim["text"] for claim in exp.claims]
    for claim in exp.claims:
        if texts.count(claim["text"]) > 1:
            raise ExperimentError(f"two claims read '{claim['text']}': give each its own text (the report lists "
                                  "them by it)")
        sides = {}
        for side in ("lower", "higher"):
            given = [str(n) for n in (claim[side] if isinstance(claim[side], list) else [claim[side]])]
            for name in given:
                valid = labels if " / " in name else names
                if name not in valid:
                    raise ExperimentError(f"claim '{claim['text']}': '{side}' names {name!r}, which is no planner, "
                                          f"sampler, swept value or group of this experiment; valid: "
                                          f"{', '.join(sorted(names))}, or a group as the report names it "
                                          f"(planner / sampler / key=value)." + suggest(name, sorted(names | labels)))
                if given.count(name) > 1:
                    raise ExperimentError(f"claim '{claim['text']}': '{side}' names {name!r} twice")
            sides[side] = set(given)
        both = sides["lower"] & sides["higher"]
        if both:
            raise ExperimentError(f"claim '{claim['text']}': {', '.join(map(repr, sorted(both)))} is on both sides: "
                                  "a claim compares two different groups")
