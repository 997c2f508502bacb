"""Helpers shared by the ``navlab`` verbs (the only module they import from each other)."""

from __future__ import annotations

from typing import Any, Dict, Tuple

import click
import yaml


def parse_params(items: Tuple[str, ...]) -> Dict[str, Any]:
    """``key=value`` pairs; values are read as YAML (numbers, lists, mappings)."""
    out: Dict[str, Any] = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise click.BadParameter(f"expected key=value, got '{item}'", param_hint="--param")
        try:
            out[key.strip()] = yaml.safe_load(value)
        except yaml.YAMLError as exc:
            raise click.BadParameter(f"cannot read the value of '{key}': {exc}", param_hint="--param") from None
    return out
