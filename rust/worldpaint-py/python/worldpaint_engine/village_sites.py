"""Village sites of a world: a JSON file listing where villages grow, of which type and size, from which seed.

    [{"x": 2500, "y": 3100, "type": "farming", "buildings": 30, "seed": 1}, ...]

``type`` is a village type of the encyclopedia (the shipped one, or ``--encyclopedia``), ``buildings`` a whole
number from 1 to 2,000, ``seed`` a whole number from 0 to 2^64 - 1 (default: the site's place in the list). Every
entry is checked before anything grows and a bad one raises ``FileFormatError`` with one line naming the file, the
site and the rule; sites off the terrain, of a type the encyclopedia lacks or too near one another are refused by
the engine, also before anything grows.
"""

from __future__ import annotations

import math

from .terrain_files import read_json, refuse

MAX_BUILDINGS = 2000
MAX_SEED = 2**64 - 1
KEYS = ("x", "y", "type", "buildings", "seed")


def whole(value, low, high):
    return isinstance(value, int) and not isinstance(value, bool) and low <= value <= high


def read_sites(path):
    """The sites of ``path`` as the engine's ``world_villages`` takes them."""
    entries = read_json(path)
    if not isinstance(entries, list) or not entries:
        raise refuse(path, 'village sites are a JSON list of {"x", "y", "type", "buildings", "seed"}, at least one')
    sites = []
    for k, entry in enumerate(entries, start=1):
        where = f"village site {k}"
        if not isinstance(entry, dict):
            raise refuse(path, f"{where} is not an object with {', '.join(KEYS)}")
        unknown = sorted(set(entry) - set(KEYS))
        if unknown:
            raise refuse(path, f"{where} has the unknown key {unknown[0]!r} (a site has {', '.join(KEYS)})")
        for key in ("x", "y"):
            v = entry.get(key)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise refuse(path, f"{where}'s {key} {v!r} is not a finite number (m)")
        if not isinstance(entry.get("type"), str) or not entry["type"]:
            raise refuse(path, f"{where} needs a village type (\"type\": \"farming\")")
        if not whole(entry.get("buildings"), 1, MAX_BUILDINGS):
            raise refuse(path, f"{where}'s buildings {entry.get('buildings')!r} is not a whole number from 1 to "
                               f"{MAX_BUILDINGS}")
        seed = entry.get("seed", k - 1)
        if not whole(seed, 0, MAX_SEED):
            raise refuse(path, f"{where}'s seed {seed!r} is not a whole number from 0 to {MAX_SEED}")
        sites.append({"position": (float(entry["x"]), float(entry["y"])), "type": entry["type"],
                      "buildings": entry["buildings"], "seed": seed})
    return sites
