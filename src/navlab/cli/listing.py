"""``navlab list``: the registered parts and their parameters."""

from __future__ import annotations

import click

from ..registry import parameters_of


def _describe(factory) -> str:
    doc = (factory.__doc__ or "").strip().splitlines()
    return doc[0] if doc else ""


@click.command("list")
def list_cmd() -> None:
    """Planners, samplers and scenes, with their parameters and defaults."""
    from ..sampling import PLANNERS, SAMPLERS
    from ..world import SCENES

    for title, registry in (("planners", PLANNERS), ("samplers", SAMPLERS)):
        click.echo(f"{title}:")
        for name in registry:
            cls = registry.get(name)
            click.echo(f"  {name:<20} {_describe(cls)}")
            params = ", ".join(f"{k}={v!r}" for k, v in parameters_of(cls).items())
            click.echo(f"  {'':<20} {params or '(no parameters)'}")
        click.echo("  (None: derived from the world, see the docs)" if title == "planners" else "")
    click.echo("scenes:")
    for name in SCENES:
        w = SCENES.get(name)()
        click.echo(f"  {name:<20} {_describe(SCENES.get(name))}")
        click.echo(f"  {'':<20} start {w.start}, goal {w.goal}, robot radius {w.robot_radius} m, "
                   f"{len(w.obstacles)} obstacles")
