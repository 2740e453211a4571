"""Arrangement colors in the scene: the guides that steer a painted pattern (where it starts, the boundary curves it
stops at, the flow curves it follows), read from curve collections, and the connectivity of a color's reference."""

import math

import bpy
import numpy as np
from mathutils import Vector

from . import WorldPaintError, engine, geometry, view

ROTATIONS = (
    ("NONE", "None", "The pattern keeps the reference's orientation"),
    ("BEST_FIT", "Best Fit", "Each neighbourhood is turned to fit the pattern around it (shape matching)"),
    ("FLOW", "Flow Field", "The pattern follows the direction of the flow curves"),
)


def curves_in(name, what):
    """World XY polylines (open splines as drawn, closed ones closed) of the curve objects of collection ``name``."""
    if not name:
        return []
    collection = bpy.data.collections.get(name)
    if collection is None:
        raise WorldPaintError(f"No collection '{name}' for the {what} curves")
    objects = [obj for obj in collection.all_objects if obj.type == 'CURVE']
    if not objects:
        raise WorldPaintError(f"The collection '{name}' holds no curve to use as {what} curves")
    closed, opened = geometry.curve_lines(objects)
    return [np.ascontiguousarray(np.vstack([c, c[:1]]), dtype=np.float64) for c in closed] + [
        np.ascontiguousarray(o, dtype=np.float64) for o in opened
    ]


def guides(context, boundaries="", flow="", start='CENTER'):
    """The engine's guides of a painted pattern: boundary and flow curves from the collections named, and the 3D
    cursor as the start when ``start`` is 'CURSOR' (else the region's centre)."""
    out = {"boundaries": curves_in(boundaries, "boundary"), "flow": curves_in(flow, "flow")}
    if start == 'CURSOR':
        out["start"] = tuple(context.scene.cursor.location[:2])
    return out


def pattern_line(summary):
    """One line saying how an arrangement color paints (``engine.ArrangementSummary``)."""
    rotation = {"none": "reference orientation", "best_fit": "best-fit rotation", "flow": "follows the flow"}
    parts = [f"{len(summary.symbols)} reference elements, {len(summary.edges)} edges"]
    if summary.lattice is not None:
        lattice = summary.lattice
        parts.append(f"a {lattice['name']} lattice {lattice['spacing']:.2f} m apart (placed within "
                     f"{lattice['spread']:.2f} m)")
    settings = summary.settings
    parts.append(rotation.get(settings["rotation"], settings["rotation"]))
    if settings["scale_noise"] > 0.0:
        parts.append(f"scale noise {settings['scale_noise']:.2f}")
    if settings["rotation_noise"] > 0.0:
        parts.append(f"rotation noise {np.degrees(settings['rotation_noise']):.0f}°")
    if settings["color_noise"] > 0.0:
        parts.append(f"color noise {settings['color_noise']:.2f}")
    if summary.flips:
        parts.append(f"{summary.flips} edges flipped")
    return ", ".join(parts)


EDGE_COLOR = (1.0, 0.75, 0.2, 1.0)
LIFT = 0.05  # metres above the terrain, so the lines are not hidden in it


class ReferenceOverlay:
    """An arrangement color's reference connectivity drawn over its elements in the viewport, while the user picks
    edges to flip."""

    def __init__(self, color_json, terrain_obj):
        self._terrain = terrain_obj
        self.update(color_json)
        self._handler = bpy.types.SpaceView3D.draw_handler_add(self._draw, (), 'WINDOW', 'POST_VIEW')

    def update(self, color_json):
        """Re-reads the color (after a flip)."""
        summary = engine.arrangement_summary(color_json)
        if summary is None:
            raise WorldPaintError("The color is not an arrangement: it has no reference to show")
        (x0, y0), _ = engine.region_bbox(engine.color_summary(color_json).region)
        self.xy = summary.positions + (x0, y0)
        self.edges = summary.edges
        top = max((self._terrain.matrix_world @ Vector(c)).z for c in self._terrain.bound_box) + 1.0
        z = []
        for x, y in self.xy:
            hit = view.ray_to_terrain(self._terrain, Vector((x, y, top)), Vector((0.0, 0.0, -1.0)))
            z.append((hit.z if hit is not None else 0.0) + LIFT)
        self.xyz = np.column_stack([self.xy, z])

    def edge_near(self, xy):
        """The edge (a, b) nearest to the XY point, if it lies within half the edge's length of it."""
        if not len(self.edges):
            return None
        a, b = self.xy[self.edges[:, 0]], self.xy[self.edges[:, 1]]
        ab = b - a
        length2 = np.maximum((ab * ab).sum(axis=1), 1e-12)
        t = np.clip(((np.asarray(xy) - a) * ab).sum(axis=1) / length2, 0.0, 1.0)
        distance = np.linalg.norm(a + t[:, None] * ab - np.asarray(xy), axis=1)
        k = int(np.argmin(distance))
        if distance[k] > 0.5 * math.sqrt(length2[k]):
            return None
        return int(self.edges[k, 0]), int(self.edges[k, 1])

    def _draw(self):
        view.draw_segments(self.xyz[np.asarray(self.edges, dtype=np.int64).reshape(-1)], EDGE_COLOR, 2.0)

    def remove(self):
        bpy.types.SpaceView3D.draw_handler_remove(self._handler, 'WINDOW')
