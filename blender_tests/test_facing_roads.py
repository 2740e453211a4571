"""Houses that face their street, as an artist sees them: the built-in Hamlet Street, whose exemplar's cottages have
their fronts (+X) to the street, appended and pasted on the demo terrain through the operators. The paste draws new
streets and turns its cottages' fronts to them, as the exemplar's are (a uniform turn would leave one in nine so;
colors learned before took the exemplar's turns about the world's axes, whatever the new streets' course). Seen:
0.98 and 0.95 of the pasted cottages near a street face it, 0.93 in the exemplar."""

import bpy
import numpy as np
from scene_kit import engine_terrain_object
from worldpaint.bridge import engine
from worldpaint.bridge.curves import structure_objects
from worldpaint.bridge.geometry import spline_control_points
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects
from worldpaint.builtin import catalog

DESTINATION = {"region_mode": 'RECT', "rect_min": (150.0, 150.0), "rect_max": (400.0, 400.0)}
NEAR = 15.0  # metres from a street's middle within which a cottage is measured (the exemplar's stand 7-11 m off)
FRONT = np.radians(20.0)  # a front within this of the way to the street faces it


def fronts_to_the_street(xy, rotation, streets):
    """The share of the points within ``NEAR`` of a street whose +X points within ``FRONT`` of the way to it, and
    how many were measured."""
    a = np.concatenate([s[:-1] for s in streets])
    b = np.concatenate([s[1:] for s in streets])
    ab = b - a
    t = np.clip(np.einsum("pnk,nk->pn", xy[:, None, :] - a[None], ab) / np.einsum("nk,nk->n", ab, ab), 0.0, 1.0)
    nearest = a[None] + t[..., None] * ab[None]
    toward = nearest - xy[:, None, :]
    distance = np.linalg.norm(toward, axis=2)
    k = np.argmin(distance, axis=1)
    rows = np.arange(len(xy))
    near = distance[rows, k] < NEAR
    way = np.arctan2(toward[rows, k, 1], toward[rows, k, 0])
    off = np.mod(rotation - way, 2.0 * np.pi)
    facing = np.minimum(off, 2.0 * np.pi - off) < FRONT
    return float(np.mean(facing[near])), int(near.sum())


def exemplar_share():
    """The share of the Hamlet Street exemplar's cottages with their fronts to the street."""
    (color,) = [c for c in catalog.COLORS if c.identifier == "HAMLET_STREET"]
    ex = color.exemplar()
    cottage = ex.category("Cottage")
    index = np.concatenate(ex.columns["category_index"])
    xy = np.concatenate(ex.columns["positions"])[index == cottage]
    rotation = np.concatenate(ex.columns["rotations"])[index == cottage]
    return fronts_to_the_street(xy, rotation, [p[:, :2] for p in ex.polylines("Street")])


def test_pasted_cottages_turn_their_fronts_to_the_new_streets():
    bpy.context.scene.worldpaint.terrain = engine_terrain_object(
        "Terrain", engine.exemplar_demo_terrain(600.0, 2.0, 7))
    assert bpy.ops.worldpaint.add_builtin_color(color='HAMLET_STREET') == {'FINISHED'}
    learned, measured = exemplar_share()
    for seed in (1, 2):
        assert bpy.ops.worldpaint.paste_color(color="Hamlet Street", seed=seed, **DESTINATION) == {'FINISHED'}
        curves = structure_objects(bpy.context.scene)["Street"]
        streets = [spline_control_points(curves, s)[:, :2] for s in curves.data.splines]
        co, rotation, _, _ = point_cloud_arrays(point_cloud_objects(bpy.context.scene)["Cottage"])
        share, near = fronts_to_the_street(co[:, :2], rotation, streets)
        print(f"seed {seed}: {share:.2f} of {near} pasted cottages within {NEAR:.0f} m of a street face it "
              f"({learned:.2f} of {measured} in the exemplar)")
        assert near >= 10, f"{near} cottages near the pasted streets"
        assert share >= 0.8, f"{share:.2f} of the pasted cottages face their street"
