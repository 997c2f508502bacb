"""``navlab.plan``: one call from a world (or scene name) to a Result."""

from __future__ import annotations

from typing import Any, Union

from .registry import parameters_of, suggest
from .result import Result
from .sampling.planners import PLANNERS, make_planner
from .sampling.samplers import SAMPLERS, GoalBiasSampler, Sampler, make_sampler
from .world import World, load_world


def split_params(planner: str, sampler: str, params: dict) -> tuple[dict, dict]:
    """Route keyword parameters to the planner or the sampler by name.

    ``goal_sample_rate`` given with a sampler that has no such parameter wraps
    that sampler in goal bias (with that probability the goal is returned).
    """
    planner_keys = set(parameters_of(PLANNERS.get(planner))) - {"sampler"}
    sampler_keys = set(parameters_of(SAMPLERS.get(sampler)))
    to_planner, to_sampler = {}, {}
    for key, value in params.items():
        if key in planner_keys:
            to_planner[key] = value
        elif key in sampler_keys or key == "goal_sample_rate":
            to_sampler[key] = value
        else:
            valid = sorted(planner_keys | sampler_keys | {"goal_sample_rate"})
            raise ValueError(f"unknown parameter '{key}' for planner '{planner}' with sampler '{sampler}'; "
                             f"valid: {', '.join(valid)}." + suggest(key, valid))
    return to_planner, to_sampler


def build_sampler(sampler: str, params: dict) -> Sampler:
    params = dict(params)
    rate = params.pop("goal_sample_rate", None) if "goal_sample_rate" not in parameters_of(SAMPLERS.get(sampler)) else None
    base = make_sampler(sampler, **params)
    if rate is None:
        return base
    wrapped = GoalBiasSampler(goal_sample_rate=rate, base=base)
    wrapped.registered_name = f"goal_bias({sampler})"  # type: ignore[attr-defined]
    return wrapped


def plan(world: Union[str, World], planner: str = "rrt_star", sampler: str = "uniform",
         seed: Any = 0, **params: Any) -> Result:
    """Plan a path in ``world`` (a World, YAML path or scene name).

    Parameters
    ----------
    world : World or str
    planner : str
        A registered planner (``navlab list``).
    sampler : str
        A registered sampler.
    seed : int or numpy.random.Generator
        The same seed gives the same result, bit for bit.
    **params
        Planner settings (``expand_dis``, ``max_iter``, ``max_time``,
        ``connect_circle_dist``, ...) and sampler settings (``goal_sample_rate``,
        ``sigma``, ``directions``, ``tolerance``, ``weights``), routed by name.

    Returns
    -------
    Result
        ``status``, ``path``, ``cost``, ``stats`` and ``params``.
    """
    w = load_world(world)
    to_planner, to_sampler = split_params(planner, sampler, params)
    samp = build_sampler(sampler, to_sampler)
    result = make_planner(planner, sampler=samp, **to_planner).plan(w, seed)
    result.params.update({"planner": planner, "sampler": sampler, "seed": seed if isinstance(seed, int) else None,
                          "world": w.name, **{k: v for k, v in samp.get_params().items() if k != "base"}})
    return result
