"""Writing an engine edit back to the point clouds.

Every painting tool returns an edit: the rows of the given ``InstanceSet`` it removed and the instances it added.
Removed hand-placed objects cannot happen (they are locked); removed cloud points are dropped, added instances are
appended to their category's cloud (made when missing), and every cloud gets its instancer. Added instances stand
on the terrain mesh (``snap``), kept ones where they stood.
"""

from dataclasses import dataclass, field

import numpy as np

from . import engine, points, snap
from .instances import point_cloud_objects


@dataclass
class Applied:
    """What writing an edit did: instances added and removed, categories left without anything to instance, and
    paths and contours added and removed."""

    added: int = 0
    removed: int = 0
    missing: list = field(default_factory=list)
    lines_added: int = 0
    lines_removed: int = 0


def added_by_category(edit, terrain_obj):
    """{category: (co (N, 3), rotation, scale, prototype, tint, stretch)} of an edit's added instances on the
    terrain, their heights on its mesh (the engine's are its heightfield's), in their prototypes' own shape."""
    on_terrain = np.isfinite(edit.heights)
    out = {}
    for index in np.unique(edit.category_index):
        mask = (edit.category_index == index) & on_terrain
        if not mask.any():
            continue  # every one off the terrain: no empty cloud for it
        co = snap.onto(terrain_obj, np.column_stack([edit.positions[mask], edit.heights[mask]]))
        out[edit.category_names[index]] = (co, edit.rotations[mask], edit.scales[mask], edit.prototype[mask],
                                           edit.tints[mask], np.ones((len(co), 3)))
    return out


def cloud_columns(instance_set, category, keep):
    """The columns of a category's cloud rows in ``instance_set`` for which ``keep`` (over all rows) holds."""
    start, stop = instance_set.cloud_rows[category]
    rows = np.arange(start, stop)[keep[start:stop]]
    co = np.column_stack([instance_set.positions[rows], instance_set.heights[rows]])
    return (co, instance_set.rotations[rows], instance_set.scales[rows], instance_set.prototype[rows],
            instance_set.tints[rows], instance_set.stretches[rows])


def apply_edit(scene, instance_set, edit, terrain_obj):
    """Writes ``edit`` (an ``engine.Edit`` relative to ``instance_set``, read from the scene) to the clouds it
    touches."""
    keep = np.ones(len(instance_set), dtype=bool)
    keep[edit.removed] = False
    added = added_by_category(edit, terrain_obj)
    clouds = point_cloud_objects(scene)
    touched = set(added)
    for category, (start, stop) in instance_set.cloud_rows.items():
        if not keep[start:stop].all():
            touched.add(category)
    out = Applied(added=sum(len(a[0]) for a in added.values()), removed=int((~keep).sum()))
    for category in sorted(touched):
        parts = [cloud_columns(instance_set, category, keep)] if category in instance_set.cloud_rows else []
        if category in added:
            parts.append(added[category])
        columns = [np.concatenate([p[k] for p in parts]) for k in range(len(parts[0]))]
        variants = variant_collection(scene, category)
        if variants is not None:
            kept = len(parts[0][0]) if category in instance_set.cloud_rows else 0
            columns[3] = variant_indices(columns[0], columns[3], kept, variants)
        obj = clouds.get(category) or points.point_cloud_object(scene, category)
        points.write_points(obj, *columns)
        if not set_instancer(scene, obj, category, terrain_obj, variants):
            out.missing.append(category)
    return out


def variant_collection(scene, category):
    """The collection of model variants a category paints with, or None."""
    item = scene.worldpaint.categories.get(category)
    variants = None if item is None else item.variants
    return variants if variants is not None and len(variants.objects) else None


def variant_indices(co, prototype, kept, variants):
    """The prototype (variant) of each point: the ``kept`` first keep theirs, the new ones take the variant least
    used within 50 m (seeded), so no two trees near each other are the same until the variants run out."""
    fixed = np.full(len(co), -1, dtype=np.int64)
    fixed[:kept] = prototype[:kept]
    return engine.assign_variants(co[:, :2], fixed, len(variants.objects)).astype(np.int32)


def set_instancer(scene, obj, category, terrain_obj, variants=None):
    """Gives a cloud its instancer with the category's prototype collection (its ``variants`` when it paints with
    some); False when it has none."""
    collection = variants or points.instancer_collection(obj)
    if not points.shows_something(collection):  # none yet, or one emptied since
        collection = points.prototype_collection(scene, category, exclude=[terrain_obj])
    points.set_instancer(obj, collection, terrain_obj)
    return collection is not None


def restore_clouds(scene, instance_set):
    """Writes the clouds back as ``instance_set`` read them (a cancelled live edit); removes clouds made since."""
    everything = np.ones(len(instance_set), dtype=bool)
    for category, obj in point_cloud_objects(scene).items():
        if category in instance_set.cloud_rows:
            points.write_points(obj, *cloud_columns(instance_set, category, everything))
        else:
            points.remove_object(obj)
