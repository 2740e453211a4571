"""Model variety as a user makes it: a low-poly tree cut into parts, edited copies of the parts made with Blender's
own tools, variants generated, a forest painted with them, and all of it kept through save and reload."""

import math

import bmesh
import bpy
import numpy as np
import pytest
from mathutils import Matrix, Vector
from scene_kit import (
    birch_variants,
    cactus,
    edited_part,
    import_birch,
    in_edit_mode,
    open_boundary,
    ring_of_parts,
    segmented_tree,
    select_only,
    slope_exemplar,
    tilt_ring,
    tree_variants,
)
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects

EXEMPLAR = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (100.0, 100.0)}


def closed(mesh):
    """Whether every edge of a mesh is shared by exactly two faces."""
    counts = {}
    for poly in mesh.polygons:
        for key in poly.edge_keys:
            counts[key] = counts.get(key, 0) + 1
    return all(c == 2 for c in counts.values())


def closed_meshes(meshes):
    """Whether every edge of each mesh is shared by exactly two faces (counted on its loops)."""
    for mesh in meshes:
        edge = np.empty(len(mesh.loops), dtype=np.int64)
        mesh.loops.foreach_get("edge_index", edge)
        if not (np.bincount(edge, minlength=len(mesh.edges)) == 2).all():
            return False
    return True


def shape_key(mesh):
    """The mesh's vertex positions rounded to 0.1 mm, as bytes: equal for two equal trees."""
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    return np.round(co, 4).tobytes()


def shapes(meshes):
    """The different shapes among ``meshes``: each a set of faces, each face its corners rounded to 0.1 mm, started
    at the least (the same model written with its faces or vertices in another order is the same shape)."""
    found = set()
    for mesh in meshes:
        co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
        mesh.vertices.foreach_get("co", co)
        co = [tuple(p) for p in np.round(co.reshape(-1, 3).astype(np.float64), 4).tolist()]
        faces = []
        for poly in mesh.polygons:
            corners = [co[v] for v in poly.vertices]
            first = corners.index(min(corners))
            faces.append(tuple(corners[first:] + corners[:first]))
        found.add(tuple(sorted(faces)))
    return found


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
    # the crown twisted by a Simple Deform and bent by a Lattice, each limited to a vertex group of the brim and the
    # apex so the ring on the trunk stays
    for name, kind in (("Crown twisted", 'SIMPLE_DEFORM'), ("Crown latticed", 'LATTICE')):
        crown = edited_part(tree, 2, name)
        group = crown.vertex_groups.new(name="top")
        group.add([v.index for v in crown.data.vertices if math.hypot(v.co.x, v.co.y) > 0.5 or v.co.z > 4.0],
                  1.0, 'REPLACE')
        modifier = crown.modifiers.new(name, kind)
        modifier.vertex_group = "top"
        if kind == 'SIMPLE_DEFORM':
            modifier.deform_method, modifier.angle = 'TWIST', math.radians(40.0)
        else:
            lattice = bpy.data.objects.new("Crown lattice", bpy.data.lattices.new("Crown lattice"))
            bpy.context.scene.collection.objects.link(lattice)
            lattice.location, lattice.scale = (0.0, 0.0, 4.5), (4.0, 4.0, 4.0)
            for point in lattice.data.points:
                if point.co.z > 0.0:
                    point.co_deform.x += 0.3
            modifier.object = lattice
    # the upper trunk leaning: its top ring turned as a solid about its centre, so the crown follows it
    tilt_ring(edited_part(tree, 1, "Trunk leaning"), 3.0, np.radians(12.0), 'X')
    return tree


def painted_forest(variants):
    """Learns the slope forest, paints it with the ``variants`` collection as its trees' prototypes; returns the
    trees' cloud, positions and variant per tree."""
    _, examples, _ = slope_exemplar()
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Forest", **EXEMPLAR) == {'FINISHED'}
    bpy.context.scene.worldpaint.categories["Tree"].variants = variants
    select_only([])
    assert bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(0.0, 100.0), rect_max=(200.0, 200.0),
                                          seed=2) == {'FINISHED'}
    cloud = point_cloud_objects(bpy.context.scene)["Tree"]
    co, _, _, prototype = point_cloud_arrays(cloud)
    return cloud, co, prototype


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
    assert settings.total == "10", "1 lower trunk x 2 upper trunks x 5 crowns"
    assert len(generated.objects) == 10, settings.report
    shapes = {tuple(np.round(np.array([v.co for v in o.data.vertices]), 4).ravel()) for o in generated.objects}
    assert len(shapes) == 10, "no two variants alike"
    for obj in generated.objects:
        assert closed(obj.data), f"{obj.name} has a crack or a hole"
        assert obj.data.materials[0] == tree.data.materials[0]
    apex_y = [max(o.data.vertices, key=lambda v: v.co.z).co.y for o in generated.objects]
    assert sum(abs(y) > 0.5 for y in apex_y) >= 5, f"the crown follows the leaning trunk: apex at y {apex_y}"

    # a forest painted with them: the trees show the variants, none repeated while others are unused nearby
    cloud, co, prototype = painted_forest(generated)
    assert set(prototype.tolist()) == set(range(10))
    counts = np.bincount(prototype, minlength=10)
    assert counts.max() - counts.min() <= 0.3 * counts.mean(), f"variants used unevenly: {counts}"
    depsgraph = bpy.context.evaluated_depsgraph_get()
    shown = {i.object.original.data.name for i in depsgraph.object_instances
             if i.is_instance and i.parent is not None and i.parent.original == cloud}
    assert shown == {o.data.name for o in generated.objects}

    blend = str(tmp_path / "variety.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    bpy.ops.wm.open_mainfile(filepath=blend)
    tree = bpy.data.objects["Column tree"]
    assert tree.worldpaint_variety.total == "10" and len(tree.worldpaint_variety.generated.objects) == 10
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


def test_seams_cut_the_model_without_new_vertices():
    tree = segmented_tree()
    mesh = tree.data
    # the two rings where the parts meet, marked as seams as a user would in Edit Mode
    for e in mesh.edges:
        z = [mesh.vertices[v].co.z for v in e.vertices]
        ring = all(abs(h - 1.5) < 1e-4 for h in z) or all(abs(h - 3.0) < 1e-4 for h in z) and all(
            math.hypot(mesh.vertices[v].co.x, mesh.vertices[v].co.y) < 0.5 for v in e.vertices)
        e.use_seam = ring
    bpy.context.view_layer.objects.active = tree
    assert bpy.ops.worldpaint.decompose_model(source='SEAMS') == {'FINISHED'}
    settings = tree.worldpaint_variety
    assert sorted(c.faces for c in settings.components) == [8, 9, 16]
    assert len(mesh.vertices) == 8 * 4 + 1, "cutting added no vertex"
    tree_variants(tree)  # the seam labels are 0 (lower trunk), 1 (upper) and 2 (crown) here too
    assert bpy.ops.worldpaint.generate_variants(count=5, seed=1) == {'FINISHED'}
    assert "% of the model's memory" in settings.report


def test_bad_input_is_refused_with_a_clear_message_and_nothing_changes():
    tree = segmented_tree()
    bpy.context.view_layer.objects.active = tree
    with pytest.raises(RuntimeError, match="Decompose 'Column tree' first"):
        bpy.ops.worldpaint.generate_variants()
    with pytest.raises(RuntimeError, match="one component only"):
        bpy.ops.worldpaint.decompose_model(source='MATERIALS')
    with pytest.raises(RuntimeError, match="no seams"):
        bpy.ops.worldpaint.decompose_model(source='SEAMS')
    assert tree.worldpaint_variety.parts is None and not tree.worldpaint_variety.components
    assert bpy.ops.worldpaint.decompose_model(source='ATTRIBUTE', attribute="part") == {'FINISHED'}
    # a part's copy that lost its vertex numbering (a mesh made elsewhere) is named in the error
    collection = tree.worldpaint_variety.parts.children[0]
    stranger = bpy.data.objects.new("Stranger", bpy.data.meshes.new("Stranger"))
    stranger.data.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
    collection.objects.link(stranger)
    with pytest.raises(RuntimeError, match="'Stranger' in 'Column tree Parts/Column tree part 0' is not a copy of a"):
        bpy.ops.worldpaint.generate_variants()
    assert tree.worldpaint_variety.generated is None


def test_the_birch_from_assets_gives_729_different_trees_and_paints_a_forest(tmp_path):
    tree = import_birch()
    assert len(tree.data.polygons) == 737 and len(tree.material_slots) == 6
    assert closed_meshes([tree.data])
    bpy.context.view_layer.objects.active = tree
    assert bpy.ops.worldpaint.decompose_model(object=tree.name, source='MATERIALS', root=0) == {'FINISHED'}
    settings = tree.worldpaint_variety
    assert settings.graph == "6 components, 5 connecting regions, a tree"
    assert [c.faces for c in settings.components] == [69, 30, 30, 256, 176, 176]
    birch_variants(tree)
    assert [len(c.objects) for c in settings.parts.children] == [3] * 6

    # asked for more than there are: every one of the 3^6 trees, once, and the report says so
    assert bpy.ops.worldpaint.generate_variants(object=tree.name, count=1000, seed=1) == {'FINISHED'}
    generated = settings.generated
    print(f"\nbirch: {settings.report}")
    assert settings.total == "729"
    assert len(generated.objects) == 729, settings.report
    assert settings.report.startswith("729 variants of 729 possible (every one tried: 1000 asked); 0 rejected")
    assert "2 solid transform" in settings.report, "each tilted branch carries its leaf mass"
    meshes = [o.data for o in generated.objects]
    assert len({shape_key(m) for m in meshes}) == 729, "no two trees alike"
    assert closed_meshes(meshes), "every tree closed: no crack at a connecting ring"
    faces = sorted(len(m.polygons) for m in meshes)
    print(f"birch: 729 distinct closed trees of {faces[0]} to {faces[-1]} faces")
    assert faces[0] < 737 == faces[-1], "thinned foliage has fewer faces"
    assert [m.name for m in meshes[0].materials] == [s.material.name for s in tree.material_slots]

    # a forest painted with them
    _, co, prototype = painted_forest(generated)
    counts = np.bincount(prototype, minlength=729)
    same = prototype[:, None] == prototype[None, :]
    np.fill_diagonal(same, False)
    gaps = np.linalg.norm(co[:, None, :2] - co[None, :, :2], axis=2)[same]
    nearest = gaps.min() if len(gaps) else math.inf
    print(f"birch forest: {len(prototype)} trees show {np.count_nonzero(counts)} of the 729 variants; two trees "
          f"alike stand {nearest:.1f} m apart at the nearest")
    assert nearest > 50.0, "no variant repeats within 50 m"
    assert np.count_nonzero(counts) >= 0.85 * len(prototype), "nearly every tree a different one"

    blend = str(tmp_path / "birch.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    bpy.ops.wm.open_mainfile(filepath=blend)
    tree = bpy.data.objects["Birch"]
    assert tree.worldpaint_variety.total == "729" and len(tree.worldpaint_variety.generated.objects) == 729
    assert len({shape_key(o.data) for o in tree.worldpaint_variety.generated.objects}) == 729
    assert bpy.context.scene.worldpaint.categories["Tree"].variants == tree.worldpaint_variety.generated


def test_parts_picked_by_hand_make_the_one_model_asked_for():
    tree = decomposed_tree_with_variants()
    settings = tree.worldpaint_variety
    leaning, tall = bpy.data.objects["Trunk leaning"], bpy.data.objects["Crown tall"]
    settings.components[1].pick, settings.components[2].pick = leaning, tall
    assert bpy.ops.worldpaint.generate_variants(object=tree.name, by_hand=True) == {'FINISHED'}
    assert bpy.ops.worldpaint.generate_variants(object=tree.name, by_hand=True) == {'FINISHED'}
    picked = list(settings.generated.objects)
    assert len(picked) == 2, "each assembly by hand adds one model"
    model = picked[0].data
    apex = max(model.vertices, key=lambda v: v.co.z).co
    tall_apex = max(tall.data.vertices, key=lambda v: v.co.z).co.z
    print(f"picked: the leaning trunk and the tall crown; apex at {tuple(round(c, 3) for c in apex)} "
          f"(the tall crown's own apex at z {tall_apex:.3f} before the lean)")
    assert abs(apex.y) > 0.5, "the crown follows the picked leaning trunk"
    assert apex.z > max(v.co.z for v in tree.data.vertices) + 0.5, "and is the tall one"
    assert closed(model)

    settings.components[2].pick = bpy.data.objects["Trunk leaning"]  # a copy of another part
    with pytest.raises(RuntimeError, match="'Trunk leaning' is not a copy in 'Column tree Parts/Column tree part 2'"):
        bpy.ops.worldpaint.generate_variants(object=tree.name, by_hand=True)
    assert len(settings.generated.objects) == 2, "nothing added"


def test_converted_objects_show_the_variant_the_instancer_showed():
    from worldpaint.bridge import points

    variants = bpy.data.collections.new("Tree variants")
    bpy.context.scene.collection.children.link(variants)
    names = ["tree 10", "tree 9", "Tree 2", "tree.001", "tree"]  # linked out of the instancer's order
    for k, name in enumerate(names):
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata([(0.0, 0.0, float(k))], [], [])
        variants.objects.link(bpy.data.objects.new(name, mesh))
    cloud = points.point_cloud_object(bpy.context.scene, "Tree")
    n = len(names)
    points.write_points(cloud, np.column_stack([np.arange(n) * 10.0, np.zeros(n), np.zeros(n)]), np.zeros(n),
                        np.ones(n), np.arange(n))
    points.set_instancer(cloud, variants)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    shown = {round(i.matrix_world.translation.x): i.object.original.data.name for i in depsgraph.object_instances
             if i.is_instance and i.parent is not None and i.parent.original == cloud}
    assert bpy.ops.worldpaint.convert_to_objects(category="Tree") == {'FINISHED'}
    converted = {round(o.location.x): o.data.name for o in bpy.data.collections["WP_Tree objects"].objects}
    print(f"instancer shows {shown}; converted {converted}")
    assert converted == shown and len(set(shown.values())) == n


def ring_section(co, sections=16):
    """The section of ``ring_of_parts`` a vertex lies on."""
    return round(math.atan2(co.y, co.x) / (2.0 * math.pi / sections)) % sections


def ring_with_copies():
    """The ring of four parts decomposed, each part with two copies edited in Edit Mode: its middle section pushed
    out from the ring's axis, its three inner sections flattened (3^4 = 81 different rings)."""
    ring = ring_of_parts()
    bpy.context.view_layer.objects.active = ring
    assert bpy.ops.worldpaint.decompose_model(object=ring.name, source='ATTRIBUTE', attribute="part",
                                              root=0) == {'FINISHED'}
    assert ring.worldpaint_variety.graph == "4 components, 4 connecting regions, fully cyclic"
    for p in range(4):
        middle = 4 * p + 2
        out = 0.2 * np.array([math.cos(middle * math.pi / 8.0), math.sin(middle * math.pi / 8.0), 0.0])
        in_edit_mode(edited_part(ring, p, f"Part {p} bulged"), lambda bm, middle=middle, out=out: bmesh.ops.translate(
            bm, vec=out, verts=[v for v in bm.verts if ring_section(v.co) == middle]))
        in_edit_mode(edited_part(ring, p, f"Part {p} flat"), lambda bm, middle=middle: bmesh.ops.scale(
            bm, vec=(1.0, 1.0, 0.6), verts=[v for v in bm.verts if abs(ring_section(v.co) - middle) <= 1]))
    return ring


def test_a_ring_of_parts_makes_each_different_ring_once():
    ring = ring_with_copies()
    settings = ring.worldpaint_variety
    # a third copy of part 1 turned whole 10 degrees about the ring's axis in Edit Mode (its two sections with it):
    # the assembly would keep the sections where parts 0 and 2 have them (counted before as a 4th piece of part 1:
    # "108 variants of 108 possible", of which 81 differ); refused now, by name
    turned = edited_part(ring, 1, "Part 1 turned")
    in_edit_mode(turned, lambda bm: bmesh.ops.rotate(bm, cent=(0.0, 0.0, 0.0), matrix=Matrix.Rotation(
        math.radians(10.0), 3, 'Z'), verts=bm.verts[:]))
    with pytest.raises(RuntimeError) as refused:
        bpy.ops.worldpaint.generate_variants(object=ring.name, count=200, seed=1)
    message = str(refused.value)
    print(f"\nring, a part turned whole in Edit Mode: {message}")
    assert "copy 'Part 1 turned' in 'Ring Parts/Ring part 1'" in message
    assert "connecting region with 'Ring Parts/Ring part 0'" in message and "the parts form a ring" in message
    assert "Object Mode" not in message
    assert settings.generated is None, "nothing made"
    bpy.data.objects.remove(turned)

    # the same turn made in Object Mode on another part's copy: its rotation is read as part of the copy, refused
    spun = edited_part(ring, 2, "Part 2 spun")
    spun.rotation_euler.z = math.radians(10.0)
    with pytest.raises(RuntimeError) as refused:
        bpy.ops.worldpaint.generate_variants(object=ring.name, count=200, seed=1)
    message = str(refused.value)
    print(f"ring, a part turned in Object Mode: {message}")
    assert "copy 'Part 2 spun' in 'Ring Parts/Ring part 2'" in message
    assert "'Part 2 spun' is turned in Object Mode" in message
    bpy.data.objects.remove(spun)

    # a copy left as it was would only repeat the original's rings
    edited_part(ring, 3, "Part 3 unedited")
    with pytest.raises(RuntimeError, match="copy 'Part 3 unedited' in 'Ring Parts/Ring part 3': no vertex"):
        bpy.ops.worldpaint.generate_variants(object=ring.name, count=200, seed=1)
    bpy.data.objects.remove(bpy.data.objects["Part 3 unedited"])

    assert bpy.ops.worldpaint.generate_variants(object=ring.name, count=200, seed=1) == {'FINISHED'}
    meshes = [o.data for o in settings.generated.objects]
    different = len(shapes(meshes))
    print(f"ring: {settings.report}; {len(meshes)} made, {different} different")
    assert settings.total == "81"
    assert settings.report.startswith("81 variants of 81 possible (every one tried: 200 asked); 0 rejected")
    assert len(meshes) == different == 81, "every ring made once"
    assert closed_meshes(meshes)


def cactus_with_copies():
    """The cactus decomposed, its parts' copies edited in Edit Mode (3^4 x 2^3 = 648 different cacti): the foot
    flared, the waist and the middle bulged or pinched, the dome raised, the top ring widened, arm A thickened or its
    elbow raised, arm B bent 15 degrees at its elbow (its ring to the tip turned as a solid: the tip follows), the
    tips' tops raised. Returns the cactus and its arms' rings."""
    plant, arms = cactus()
    bpy.context.view_layer.objects.active = plant
    assert bpy.ops.worldpaint.decompose_model(object=plant.name, source='ATTRIBUTE', attribute="part",
                                              root=0) == {'FINISHED'}
    assert plant.worldpaint_variety.graph == "7 components, 6 connecting regions, a tree"

    def on(ring):
        return lambda co: np.min(np.linalg.norm(np.asarray(ring) - np.array(co), axis=1)) < 1e-4

    def trunk(r):
        return lambda co: abs(math.hypot(co.x, co.y) - 0.5) < 1e-4 and abs(co.z - 0.8 * r) < 1e-4

    def edit(label, name, operation, where, free_only=False):
        copy = edited_part(plant, label, name)
        free = ~open_boundary(copy.data) if free_only else np.ones(len(copy.data.vertices), dtype=bool)
        in_edit_mode(copy, lambda bm: operation(bm, [v for v in bm.verts if where(v.co) and free[v.index]]))

    def scale(factor, centre=(0.0, 0.0, 0.0)):
        return lambda bm, verts: bmesh.ops.scale(bm, vec=factor, space=Matrix.Translation(-Vector(centre)),
                                                 verts=verts)

    def lift(dz):
        return lambda bm, verts: bmesh.ops.translate(bm, vec=(0.0, 0.0, dz), verts=verts)

    edit(0, "Foot flared", scale((1.3, 1.3, 1.0)), trunk(0))
    edit(0, "Waist bulged", scale((1.15, 1.15, 1.0)), trunk(2), free_only=True)
    edit(1, "Middle bulged", scale((1.15, 1.15, 1.0)), trunk(4), free_only=True)
    edit(1, "Middle pinched", scale((0.88, 0.88, 1.0)), trunk(5), free_only=True)
    edit(2, "Dome raised", lift(0.5), lambda co: co.z > 6.5)
    edit(2, "Top widened", scale((1.15, 1.15, 1.0)), trunk(7))
    edit(3, "Arm A thick", scale((1.3, 1.3, 1.3), arms[0][1].mean(axis=0)), on(arms[0][1]))
    edit(3, "Arm A elbow up", lift(0.15), on(arms[0][2]))
    edit(4, "Tip A raised", lift(0.3), on(arms[0][5]))
    elbow, out = arms[1][1].mean(axis=0), arms[1][1].mean(axis=0) - arms[1][0].mean(axis=0)
    axis = np.cross((0.0, 0.0, 1.0), out)
    bend = Matrix.Rotation(math.radians(15.0), 3, Vector(axis / np.linalg.norm(axis)))
    edit(5, "Arm B bent", lambda bm, verts: bmesh.ops.rotate(bm, cent=elbow, matrix=bend, verts=verts),
         lambda co: on(arms[1][2])(co) or on(arms[1][3])(co))
    edit(6, "Tip B raised", lift(0.3), on(arms[1][5]))
    return plant, arms


def test_a_cactus_with_turned_arms_makes_each_different_cactus_once():
    plant, arms = cactus_with_copies()
    settings = plant.worldpaint_variety
    # arm A's copy turned 20 degrees about the cactus's axis in Object Mode (counted before as a 4th piece of the
    # arm: "864 variants of 864 possible", of which 648 differ): read as part of the copy, and refused by name
    turned = edited_part(plant, 3, "Arm turned")
    turned.rotation_euler.z = math.radians(20.0)
    with pytest.raises(RuntimeError) as refused:
        bpy.ops.worldpaint.generate_variants(object=plant.name, count=1000, seed=1)
    message = str(refused.value)
    print(f"\ncactus, an arm turned in Object Mode: {message}")
    for needle in ("copy 'Arm turned' in 'Cactus Parts/Cactus part 3'",
                   "turns or moves its connecting region with 'Cactus Parts/Cactus part 0' as one solid together "
                   "with the whole piece", "turn the rest of the piece about it",
                   "'Arm turned' is turned in Object Mode"):
        assert needle in message
    assert settings.generated is None, "nothing made"
    # the same turn made in Edit Mode, on the copy's mesh: refused the same way
    turned.rotation_euler.z = 0.0
    in_edit_mode(turned, lambda bm: bmesh.ops.rotate(bm, cent=(0.0, 0.0, 0.0), matrix=Matrix.Rotation(
        math.radians(20.0), 3, 'Z'), verts=bm.verts[:]))
    with pytest.raises(RuntimeError, match="copy 'Arm turned' in 'Cactus Parts/Cactus part 3': it turns or moves"):
        bpy.ops.worldpaint.generate_variants(object=plant.name, count=1000, seed=1)
    bpy.data.objects.remove(turned)

    assert bpy.ops.worldpaint.generate_variants(object=plant.name, count=1000, seed=1) == {'FINISHED'}
    meshes = [o.data for o in settings.generated.objects]
    different = len(shapes(meshes))
    print(f"cactus: {settings.report}; {len(meshes)} made, {different} different")
    assert settings.total == "648"
    assert settings.report.startswith("648 variants of 648 possible (every one tried: 1000 asked); 0 rejected")
    assert "1 solid transform" in settings.report, "arm B's bent copy"
    assert len(meshes) == different == 648, "every cactus made once"
    assert closed_meshes(meshes)
    # arm B's bent copy shows: in half the cacti the ring where its tip starts is away from the original arm's
    ring = arms[1][3]
    moved = 0
    for mesh in meshes:
        co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
        mesh.vertices.foreach_get("co", co)
        moved += np.min(np.linalg.norm(co.reshape(-1, 3)[:, None] - ring, axis=2), axis=0).max() > 0.1
    assert moved == 324, moved

    # the top stretched 25 % upwards in Object Mode (about the cactus's foot): read as part of the copy, its ring on
    # the middle part brought back, the dome stands higher in the model assembled by hand
    stretched = edited_part(plant, 2, "Top stretched")
    stretched.scale.z = 1.25
    settings.components[2].pick = stretched
    assert bpy.ops.worldpaint.generate_variants(object=plant.name, by_hand=True) == {'FINISHED'}
    assert settings.total == "864"
    picked = bpy.data.objects[f"{plant.name} picked variant 000"].data
    apex = max(v.co.z for v in picked.vertices)
    print(f"cactus, the top stretched in Object Mode: the dome's apex at {apex:.3f} m (7.000 m before)")
    assert abs(apex - (4.8 + 1.25 * 2.2)) < 1e-4

    # a copy of arm A whose elbow is pushed back into the trunk, picked by hand: the model is refused, naming the picks
    poked = edited_part(plant, 3, "Arm A poked")
    elbow = arms[0][2]
    back = -1.3 * (elbow.mean(axis=0) * (1.0, 1.0, 0.0)) / np.linalg.norm(elbow.mean(axis=0)[:2])
    in_edit_mode(poked, lambda bm: bmesh.ops.translate(bm, vec=back, verts=[
        v for v in bm.verts if np.min(np.linalg.norm(elbow - np.array(v.co), axis=1)) < 1e-4]))
    settings.components[3].pick = poked
    with pytest.raises(RuntimeError) as refused:
        bpy.ops.worldpaint.generate_variants(object=plant.name, by_hand=True)
    message = str(refused.value)
    print(f"cactus, an arm poked into the trunk picked by hand: {message}")
    assert ("The picked copies ('Top stretched' in 'Cactus Parts/Cactus part 2', 'Arm A poked' in 'Cactus "
            "Parts/Cactus part 3') make a model whose faces intersect") in message
    assert len(settings.generated.objects) == 649, "nothing added"
