"""``python -m navlab``: the navlab command."""

from .command import main

main()
