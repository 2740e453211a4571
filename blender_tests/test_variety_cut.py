"""Cutting a model where the user drew a path, and its component graph: a ring drawn around a column cuts it with
new vertices whose texture coordinates are interpolated, the cut becomes the seam Decompose Model cuts it by."""

import math

import bmesh
import bpy
import numpy as np
import pytest
from scene_kit import poly_curve
from worldpaint.bridge import variety, variety_cut
from worldpaint.ops import variety_tools


def column(height=4.0, radius=0.5, sides=8):
    """A capped column from z = −height/2 to height/2 with cylindrical texture coordinates: u the angle around it
    (a turn is 1), v = z / height + ½ on its side."""
    bm = bmesh.new()
    bmesh.ops.create_cone(bm, cap_ends=True, segments=sides, radius1=radius, radius2=radius, depth=height)
    uv = bm.loops.layers.uv.new("UVMap")
    for face in bm.faces:
        side = abs(face.normal.z) < 0.5
        for loop in face.loops:
            x, y, z = loop.vert.co
            angle = (math.atan2(y, x) / math.tau) % 1.0
            loop[uv].uv = (angle, z / height + 0.5) if side else (0.5 + 0.5 * x / radius, 0.5 + 0.5 * y / radius)
    mesh = bpy.data.meshes.new("Column")
    bm.to_mesh(mesh)
    bm.free()
    obj = bpy.data.objects.new("Column", mesh)
    bpy.context.scene.collection.objects.link(obj)
    obj.location = (3.0, -2.0, 1.0)  # the cut works in the object's own space
    bpy.context.view_layer.objects.active = obj
    return obj


def ring(z, radius=0.9, count=12, wobble=0.1, seed=2):
    """A closed path around the column at height z (world), drawn by a slightly unsteady hand."""
    rng = np.random.default_rng(seed)
    angle = np.linspace(0.0, math.tau, count, endpoint=False)
    r = radius + rng.uniform(-wobble, wobble, count)
    return np.column_stack([3.0 + r * np.cos(angle), -2.0 + r * np.sin(angle), np.full(count, z)])


def loop_uvs(mesh):
    uvs = np.empty(len(mesh.loops) * 2, dtype=np.float64)
    mesh.uv_layers.active.data.foreach_get("uv", uvs)
    corners = np.empty(len(mesh.loops), dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", corners)
    return corners, uvs.reshape(-1, 2)


def test_a_ring_drawn_around_a_column_cuts_it_with_interpolated_uvs():
    obj = column()
    before = len(obj.data.vertices)
    poly_curve("Cut", ring(z=2.0), cyclic=True)  # world z 2 is the column's z 1: a quarter from its top
    assert bpy.ops.worldpaint.cut_model(object="Column", curve="Cut") == {'FINISHED'}
    mesh = obj.data
    new = np.arange(before, len(mesh.vertices))
    co = np.array([tuple(mesh.vertices[i].co) for i in new])
    print(f"cut: {len(new)} new vertices at z {co[:, 2].min():.4f}–{co[:, 2].max():.4f}")
    assert len(new) == 8 and np.allclose(co[:, 2], 1.0, atol=1e-5), "one new vertex on each of the 8 side edges"
    corners, uvs = loop_uvs(mesh)
    side = [k for k in range(len(corners)) if corners[k] >= before]
    for k in side:
        x, y, _ = mesh.vertices[corners[k]].co
        u = (math.atan2(y, x) / math.tau) % 1.0
        assert uvs[k, 1] == pytest.approx(0.75, abs=1e-5), "v interpolated along the edge: z 1 of 4 m above centre"
        assert min(abs(uvs[k, 0] - u), 1.0 - abs(uvs[k, 0] - u)) < 1e-5, "u kept: the angle around (1 wraps to 0)"
    seams = np.empty(len(mesh.edges), dtype=bool)
    mesh.edges.foreach_get("use_seam", seams)
    assert seams.sum() == 8 and obj.worldpaint_variety.source == 'SEAMS'
    assert int(variety.seam_islands(obj).max()) + 1 == 2

    assert bpy.ops.worldpaint.decompose_model(object="Column", source='SEAMS') == {'FINISHED'}
    assert obj.worldpaint_variety.graph.startswith("2 components, 1 connecting regions")
    lines = variety_cut.graph_lines(obj, variety.face_labels(obj, 'SEAMS'))
    joint = lines[0, 1]
    print(f"component graph: {len(lines)} segments, joint at {np.round(joint, 3)}")
    assert len(lines) == 2 and np.allclose(joint, (3.0, -2.0, 2.0), atol=1e-6), "through the ring's centre"
    assert (lines[0, 0, 2] - 2.0) * (lines[1, 1, 2] - 2.0) < 0.0, "the parts' centres on either side of it"
    assert bpy.ops.worldpaint.component_graph(object="Column") == {'FINISHED'}
    assert variety_tools.shown(obj), "the graph is drawn"
    assert bpy.ops.worldpaint.component_graph(object="Column") == {'FINISHED'}
    assert not variety_tools.shown(obj), "a second click hides it"


def test_a_bad_path_is_refused_and_the_model_is_unchanged():
    obj = column()
    before = len(obj.data.vertices)
    poly_curve("Line", [(3.0, -3.0, 1.5), (3.0, -1.0, 1.5)])
    poly_curve("Far", ring(z=40.0))
    for curve, message in (("Line", "three points"), ("Far", "not near"), ("", "Pick a curve")):
        with pytest.raises(RuntimeError, match=message):
            bpy.ops.worldpaint.cut_model(object="Column", curve=curve)
        assert len(obj.data.vertices) == before


def test_selected_faces_marked_as_components_decompose_the_model():
    obj = column()
    poly_curve("Cut", ring(z=2.0), cyclic=True)
    assert bpy.ops.worldpaint.cut_model(object="Column", curve="Cut") == {'FINISHED'}
    mesh = obj.data
    centres = np.empty(len(mesh.polygons) * 3)
    mesh.polygons.foreach_get("center", centres)
    top = centres.reshape(-1, 3)[:, 2] > 1.0
    with pytest.raises(RuntimeError, match="Select the faces"):
        mesh.polygons.foreach_set("select", np.zeros(len(top), dtype=bool))
        bpy.ops.worldpaint.mark_component(object="Column")
    mesh.polygons.foreach_set("select", top)
    bpy.ops.object.mode_set(mode='EDIT')
    assert bpy.ops.worldpaint.mark_component(object="Column") == {'FINISHED'}
    assert obj.mode == 'EDIT', "Edit Mode stays"
    bpy.ops.object.mode_set(mode='OBJECT')
    labels = variety.face_labels(obj, 'ATTRIBUTE', variety.COMPONENT_ATTRIBUTE)
    print(f"marked: {int(top.sum())} selected faces labelled {sorted(set(labels[top].tolist()))}, "
          f"the other {int((~top).sum())} {sorted(set(labels[~top].tolist()))}")
    assert set(labels[top].tolist()) == {1} and set(labels[~top].tolist()) == {0}
    settings = obj.worldpaint_variety
    assert (settings.source, settings.attribute) == ('ATTRIBUTE', variety.COMPONENT_ATTRIBUTE)
    assert bpy.ops.worldpaint.decompose_model(object="Column", source='ATTRIBUTE',
                                              attribute=variety.COMPONENT_ATTRIBUTE) == {'FINISHED'}
    assert settings.graph.startswith("2 components, 1 connecting regions")
