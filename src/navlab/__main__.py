"""``python -m navlab``: the navlab command."""

from .cli import main

main()
