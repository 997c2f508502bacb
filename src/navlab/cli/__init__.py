"""The ``navlab`` command: one module per verb, sharing only :mod:`.common`."""

from __future__ import annotations

import sys

import click

from ..registry import UnknownNameError


class NavlabGroup(click.Group):
    """Turns navlab's input errors into one clean line and exit status 2."""

    def invoke(self, ctx):
        from ..world.io import WorldFormatError

        try:
            return super().invoke(ctx)
        except (UnknownNameError, WorldFormatError, ValueError, FileNotFoundError) as exc:  # MapFormatError too
            click.echo(f"Error: {exc}", err=True)
            sys.exit(2)


@click.group(cls=NavlabGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="navlab")
def main() -> None:
    """navlab: 2D mobile-robot path planning and navigation.

    Worlds are YAML world files or built-in scene names (see `navlab list`).
    Units are metres and radians unless a flag says otherwise.
    """


from .bench import bench_cmd  # noqa: E402
from .grid import grid_group  # noqa: E402
from .listing import list_cmd  # noqa: E402
from .plan import plan_cmd  # noqa: E402
from .ros import ros_group  # noqa: E402
from .sim import sim_cmd  # noqa: E402

for _command in (plan_cmd, list_cmd, grid_group, bench_cmd, sim_cmd, ros_group):
    main.add_command(_command)

if __name__ == "__main__":  # pragma: no cover
    main()
