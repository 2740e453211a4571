"""Model variety as a user makes it: a low-poly tree cut into parts, edited copies of the parts made with Blender's
own tools, variants generated, a forest painted with them, and all of it kept through save and reload."""

import math

import bpy
import numpy as np
import pytest
from scene_kit import edited_part, segmented_tree, select_only, slope_exemplar, tilt_ring, tree_variants
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects

EXEMPLAR = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (100.0, 100.0)}


def closed(mesh):
    """Whether every edge of a mesh is shared by exactly two faces."""
    counts = {}
    for poly in mesh.polygons:
        for key in poly.edge_keys:
            counts[key] = counts.get(key, 0) + 1
    return all(c == 2 for c in counts.values())


def decomposed_tree_with_variants():
    tree = segmented_tree()
    bpy.context.view_layer.objects.active = tree
    assert bpy.ops.worldpaint.decompose_model(object=tree.name, source='ATTRIBUTE', attribute="part",
                                              root=0) == {'FINISHED'}
    # the crown taller (a local change: its ring to the trunk untouched), by moving the apex in the mesh
    tall = edited_part(tree, 2, "Crown tall")
    apex = max(tall.data.vertices, key=lambda v: v.co.z)
    apex.co.z += 1.0
    # the crown narrower: its brim drawn in, its ring to the trunk untouched (a local change too)
    narrow = edited_part(tree, 2, "Crown narrow")
    for v in narrow.data.vertices:
        if math.hypot(v.co.x, v.co.y) > 0.5:
            v.co.x, v.co.y = 0.7 * v.co.x, 0.7 * v.co.y
    # the upper trunk leaning: its top ring turned as a solid about its centre, so the crown follows it
    tilt_ring(edited_part(tree, 1, "Trunk leaning"), 3.0, np.radians(12.0), 'X')
    return tree


def test_decompose_finds_the_parts_and_their_connecting_rings():
    tree = segmented_tree()
    bpy.context.view_layer.objects.active = tree
    assert bpy.ops.worldpaint.decompose_model(source='ATTRIBUTE', attribute="part") == {'FINISHED'}
    settings = tree.worldpaint_variety
    assert [c.label for c in settings.components] == [0, 1, 2]
    assert settings.graph == "3 components, 2 connecting regions, a tree"
    assert [c.regions for c in settings.components] == ["part 1", "part 0, part 2", "part 1"]
    pieces = [o for c in settings.parts.children for o in c.objects]
    assert sum(len(o.data.polygons) for o in pieces) == len(tree.data.polygons)
    with pytest.raises(RuntimeError, match="no face sets"):
        bpy.ops.worldpaint.decompose_model(source='FACE_SETS')


def test_generated_variants_are_distinct_crack_free_and_paint_a_forest(tmp_path):
    tree = decomposed_tree_with_variants()
    assert bpy.ops.worldpaint.generate_variants(object=tree.name, count=20, seed=1) == {'FINISHED'}
    settings = tree.worldpaint_variety
    generated = settings.generated
    assert settings.total == "6", "1 lower trunk x 2 upper trunks x 3 crowns"
    assert len(generated.objects) == 6, settings.report
    shapes = {tuple(np.round(np.array([v.co for v in o.data.vertices]), 4).ravel()) for o in generated.objects}
    assert len(shapes) == 6, "no two variants alike"
    for obj in generated.objects:
        assert closed(obj.data), f"{obj.name} has a crack or a hole"
        assert obj.data.materials[0] == tree.data.materials[0]
    apex_y = [max(o.data.vertices, key=lambda v: v.co.z).co.y for o in generated.objects]
    assert sum(abs(y) > 0.5 for y in apex_y) == 3, f"the crown follows the leaning trunk: apex at y {apex_y}"

    # a forest painted with them: the trees show the variants, none repeated while others are unused nearby
    _, examples, _ = slope_exemplar()
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Forest", **EXEMPLAR) == {'FINISHED'}
    bpy.context.scene.worldpaint.categories["Tree"].variants = generated
    select_only([])
    assert bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(0.0, 100.0), rect_max=(200.0, 200.0),
                                          seed=2) == {'FINISHED'}
    cloud = point_cloud_objects(bpy.context.scene)["Tree"]
    co, _, _, prototype = point_cloud_arrays(cloud)
    assert set(prototype.tolist()) == set(range(6))
    counts = np.bincount(prototype, minlength=6)
    assert counts.max() - counts.min() <= 0.3 * counts.mean(), f"variants used unevenly: {counts}"
    depsgraph = bpy.context.evaluated_depsgraph_get()
    shown = {i.object.original.data.name for i in depsgraph.object_instances
             if i.is_instance and i.parent is not None and i.parent.original == cloud}
    assert shown == {o.data.name for o in generated.objects}

    blend = str(tmp_path / "variety.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    bpy.ops.wm.open_mainfile(filepath=blend)
    tree = bpy.data.objects["Column tree"]
    assert tree.worldpaint_variety.total == "6" and len(tree.worldpaint_variety.generated.objects) == 6
    assert bpy.context.scene.worldpaint.categories["Tree"].variants == tree.worldpaint_variety.generated


def test_thirty_six_trees_from_nine_edited_parts():
    tree = segmented_tree()
    bpy.context.view_layer.objects.active = tree
    assert bpy.ops.worldpaint.decompose_model(source='ATTRIBUTE', attribute="part", root=0) == {'FINISHED'}
    tree_variants(tree)
    assert bpy.ops.worldpaint.generate_variants(count=36, seed=3) == {'FINISHED'}
    settings = tree.worldpaint_variety
    assert settings.total == "36" and len(settings.generated.objects) == 36, settings.report
    assert all(closed(o.data) for o in settings.generated.objects)
