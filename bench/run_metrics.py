"""Shared by the benchmark tables: a run folder's metrics.json, or None when it has none."""
import json


def load(path):
    try:
        with open(path / "metrics.json") as f:
            return json.load(f)
    except (OSError, ValueError):
        return None
