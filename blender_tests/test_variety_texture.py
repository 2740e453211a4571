"""Texture variety as a user makes it (Maréchal et al. §5): details painted onto copies of a tree's texture become
texture components, packed into the fewest atlases with no two conflicting ones together; every generated variant
keeps the tree's texture coordinates and shows the components it picked, and all of it is kept through save and
reload."""

import math

import bpy
import numpy as np
import pytest
from scene_kit import segmented_tree, tree_variants
from worldpaint.bridge.compat import node_material

SIZE, GRID, CELL = 48, 6, 8  # a 48² texture; face f owns the 8² cell (f % 6, f // 6), its UVs a texel inside it
TRUNK, CROWN, GREY = (110, 70, 40, 255), (40, 120, 50, 255), (128, 128, 128, 255)
RED, BLUE, YELLOW = (220, 30, 30, 255), (30, 60, 220, 255), (240, 220, 30, 255)
# the edits as a user paints them: red and blue over the same crown face (they conflict: face 17 shows both), yellow
# on a trunk face and another crown face (free of both)
EDITS = {"Red": (RED, (17, 19)), "Blue": (BLUE, (17, 21)), "Yellow": (YELLOW, (5, 29))}
N = 400


def face_corners(n):
    """A face's UV corners in its cell, in texels: a quad, a triangle or a polygon, a texel inside the cell's edge."""
    if n == 4:
        return [(1, 1), (7, 1), (7, 7), (1, 7)]
    if n == 3:
        return [(1, 1), (7, 1), (4, 7)]
    return [(4 + 3 * math.cos(2 * math.pi * k / n), 4 + 3 * math.sin(2 * math.pi * k / n)) for k in range(n)]


def textured_tree():
    """``segmented_tree`` with a UV map (each face in its own cell) and a base texture: trunk cells brown, crown cells
    green, the rest grey, shown by an Image Texture in its material."""
    tree = segmented_tree("Painted tree")
    mesh = tree.data
    uv, texels = [], np.zeros((SIZE, SIZE, 4), dtype=np.uint8)
    texels[:] = GREY
    parts = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.attributes["part"].data.foreach_get("value", parts)
    for poly in mesh.polygons:
        cx, cy = (poly.index % GRID) * CELL, (poly.index // GRID) * CELL
        uv += [((cx + x) / SIZE, (cy + y) / SIZE) for x, y in face_corners(poly.loop_total)]
        texels[cy:cy + CELL, cx:cx + CELL] = CROWN if parts[poly.index] == 2 else TRUNK
    texels[::2, ::2, :3] -= 12  # a fine pattern, so the texture is not flat
    mesh.uv_layers.new(name="UVMap").data.foreach_set("uv", np.asarray(uv, dtype=np.float32).ravel())
    base = bpy.data.images.new("Tree texture", SIZE, SIZE, alpha=True)
    write_pixels(base, texels)
    base.pack()
    material = node_material("Tree bark")
    node = material.node_tree.nodes.new('ShaderNodeTexImage')
    node.image = base
    material.node_tree.nodes.active = node
    bsdf = next(n for n in material.node_tree.nodes if n.type == 'BSDF_PRINCIPLED')
    material.node_tree.links.new(node.outputs["Color"], bsdf.inputs["Base Color"])
    mesh.materials.clear()
    mesh.materials.append(material)
    return tree, base


def write_pixels(image, rgba):
    image.pixels.foreach_set((np.asarray(rgba, dtype=np.float32) / 255.0).ravel())


def read_pixels(image):
    width, height = image.size
    out = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(out)
    return np.rint(out * 255.0).astype(np.int64).reshape(height, width, 4)


def centroid_texel(uv):
    """The texel under a face's UV centroid (x, y)."""
    c = np.asarray(uv, dtype=np.float64).mean(axis=0)
    return int(c[0] * SIZE), int(c[1] * SIZE)


def paint_edits(tree):
    """Three texture edits made with New Texture Edit and painted (pixels written, as a brush would): a 2² dab at the
    centre of each of their faces."""
    uv = face_uvs(tree.data)
    for name, (colour, faces) in EDITS.items():
        assert bpy.ops.worldpaint.add_texture_edit(object=tree.name, name=name) == {'FINISHED'}
        image = bpy.data.images[name]
        assert bpy.context.scene.tool_settings.image_paint.canvas == image, "the new edit is the paint canvas"
        texels = read_pixels(image)
        for f in faces:
            x, y = centroid_texel(uv[f])
            texels[y - 1:y + 1, x - 1:x + 1] = colour
        write_pixels(image, texels)


def face_uvs(mesh):
    """Each face's UV corners (float32)."""
    uv = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    mesh.uv_layers.active.data.foreach_get("uv", uv)
    uv = uv.reshape(-1, 2)
    return [uv[p.loop_start:p.loop_start + p.loop_total] for p in mesh.polygons]


def shown_image(obj, face):
    """The image a face of a variant shows: its material's Image Texture's."""
    material = obj.data.materials[obj.data.polygons[face].material_index]
    return next(n.image for n in material.node_tree.nodes if n.type == 'TEX_IMAGE')


def face_origin(obj):
    origin = np.empty(len(obj.data.polygons), dtype=np.int64)
    obj.data.attributes["wp_face"].data.foreach_get("value", origin)
    return origin


def test_painted_details_become_components_packed_in_the_fewest_atlases(tmp_path):
    tree, base = textured_tree()
    bpy.context.view_layer.objects.active = tree
    assert bpy.ops.worldpaint.decompose_model(object=tree.name, source='ATTRIBUTE', attribute="part",
                                              root=0) == {'FINISHED'}
    tree_variants(tree)  # 36 shapes
    paint_edits(tree)
    settings = tree.worldpaint_variety
    assert [e.image.name for e in settings.texture_edits] == list(EDITS)
    original_uv = face_uvs(tree.data)
    base_texels = read_pixels(base)

    assert bpy.ops.worldpaint.generate_variants(object=tree.name, count=N, seed=5) == {'FINISHED'}
    print(f"\n  {settings.report}\n  {settings.texture_report}")
    variants = sorted(settings.generated.objects, key=lambda o: o.name)
    assert len(variants) == N and settings.report.startswith("400 variants, 36 shapes of 36 possible"), \
        "400 variants from 36 shapes and the texture components"

    # the packing: red and blue conflict (face 17 shows both), so they are in two atlases; yellow joins one of them
    atlases = {item.image.name: item.edits.split(", ") for item in settings.atlases}
    print(f"  atlases: {atlases}")
    assert len(atlases) == 2, "the fewest atlases for one conflicting pair"
    assert not any({"Red", "Blue"} <= set(edits) for edits in atlases.values()), "conflicting edits share an atlas"
    assert sorted(sum(atlases.values(), [])) == ["Blue", "Red", "Yellow"]
    assert "2 atlases (the fewest), 1 conflicting pair;" in settings.texture_report

    counts = {name: 0 for name in EDITS}
    plain = 0
    for obj in variants:
        origin = face_origin(obj)
        uv = face_uvs(obj.data)
        # texture coordinates unchanged, byte for byte: each face's UVs are those of the original face it copies
        assert (origin >= 0).all()
        assert np.concatenate(uv).tobytes() == np.concatenate([original_uv[o] for o in origin]).tobytes()
        chosen = [list(EDITS)[k] for k in obj["wp_texture_edits"]]
        assert not {"Red", "Blue"} <= set(chosen), "face locking: face 17 shows one of them"
        for name in chosen:
            counts[name] += 1
        plain += not chosen
        # each face samples, at its UV centroid in the image it shows, the colour painted there or the base texture
        for f, o in enumerate(origin):
            image = shown_image(obj, f)
            x, y = centroid_texel(uv[f])
            painted = [EDITS[name][0] for name in chosen if o in EDITS[name][1]]
            expected = painted[0] if painted else tuple(base_texels[y, x])
            assert tuple(read_pixels(image)[y, x]) == expected, f"{obj.name} face {f} (copies {o}) in {image.name}"
            if not chosen:
                assert image == base, "a variant that took no component shows the base texture"

    # each component is taken with probability 0.5 unless a taken one locked its faces first: red and blue lock each
    # other (taken first, ½ · 0.5, or second when the other was not, ½ · 0.5 · 0.5: 0.375 each), yellow is free
    expected = {"Red": 0.375, "Blue": 0.375, "Yellow": 0.5}
    print("  taken: " + ", ".join(f"{name} {counts[name]}/{N} (expected {expected[name] * N:.0f})" for name in EDITS)
          + f"; {plain} variants plain")
    for name, p in expected.items():
        assert abs(counts[name] - p * N) < 4 * math.sqrt(N * p * (1 - p)), f"{name} taken {counts[name]} times"
    # plain: neither red nor blue (each visited, 0.5 · 0.5) and no yellow (0.5): 0.125
    assert abs(plain - 0.125 * N) < 4 * math.sqrt(N * 0.125 * 0.875)

    # save and reload: the edits (packed with what was painted), the setting, the atlases and the variants stay
    atlas_texels = {name: read_pixels(bpy.data.images[name]) for name in atlases}
    edit_texels = {name: read_pixels(bpy.data.images[name]) for name in EDITS}
    shown = [(o.name, [m.name for m in o.data.materials], [p.material_index for p in o.data.polygons])
             for o in variants[:20]]
    blend = str(tmp_path / "texture_variety.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    bpy.ops.wm.open_mainfile(filepath=blend)
    settings = bpy.data.objects["Painted tree"].worldpaint_variety
    assert [e.image.name for e in settings.texture_edits] == list(EDITS)
    assert settings.texture_probability == 0.5 and settings.base_image is None
    assert {item.image.name: item.edits.split(", ") for item in settings.atlases} == atlases
    for name, texels in {**atlas_texels, **edit_texels}.items():
        assert np.array_equal(read_pixels(bpy.data.images[name]), texels), f"{name} changed on reload"
    reloaded = {o.name: o for o in settings.generated.objects}
    for name, materials, slots in shown:
        assert [m.name for m in reloaded[name].data.materials] == materials
        assert [p.material_index for p in reloaded[name].data.polygons] == slots


def test_fewer_shapes_than_asked_repeat_with_other_textures_and_the_probability_is_kept():
    tree, _base = textured_tree()
    bpy.context.view_layer.objects.active = tree
    assert bpy.ops.worldpaint.decompose_model(source='ATTRIBUTE', attribute="part", root=0) == {'FINISHED'}
    paint_edits(tree)
    settings = tree.worldpaint_variety
    settings.texture_probability = 0.9  # the panel's setting, used when the call does not give one
    assert bpy.ops.worldpaint.generate_variants(count=60, seed=2) == {'FINISHED'}
    variants = list(settings.generated.objects)
    assert len(variants) == 60 and settings.report.startswith("60 variants, 1 shape of 1 possible"), \
        "one shape (nothing edited), 60 variants told apart by their textures"
    yellow = sum(2 in o["wp_texture_edits"] for o in variants)
    print(f"\n  probability 0.9: yellow taken by {yellow}/60")
    assert yellow >= 48
    assert settings.texture_probability == pytest.approx(0.9)
    # the same seed gives the same picks
    picks = [list(o["wp_texture_edits"]) for o in sorted(variants, key=lambda o: o.name)]
    assert bpy.ops.worldpaint.generate_variants(count=60, seed=2) == {'FINISHED'}
    again = [list(o["wp_texture_edits"]) for o in sorted(settings.generated.objects, key=lambda o: o.name)]
    assert again == picks
    atlases = [i.name for i in bpy.data.images if i.name.startswith("Painted tree atlas")]
    materials = [m.name for m in bpy.data.materials if m.name.startswith("Tree bark (")]
    assert len(settings.atlases) == 2 and len(atlases) == 2, "generating again replaces the atlases"
    assert materials == ["Tree bark (Painted tree atlas 1)", "Tree bark (Painted tree atlas 2)"], materials

    # generating with another seed is one undo step: undone, the variants, atlases and materials are those before
    atlas_texels = {name: read_pixels(bpy.data.images[name]) for name in atlases}
    bpy.ops.ed.undo_push(message="variants of seed 2")
    assert bpy.ops.worldpaint.generate_variants(count=60, seed=3, probability=0.2) == {'FINISHED'}
    bpy.ops.ed.undo_push(message="Generate Variants")
    assert [list(o["wp_texture_edits"]) for o in sorted(settings.generated.objects, key=lambda o: o.name)] != picks
    bpy.ops.ed.undo()
    settings = bpy.data.objects["Painted tree"].worldpaint_variety
    assert settings.texture_probability == pytest.approx(0.9)
    assert [list(o["wp_texture_edits"]) for o in sorted(settings.generated.objects, key=lambda o: o.name)] == picks
    assert len(bpy.data.objects) == 1 + 3 + 60 and len([m for m in bpy.data.materials if m.name in materials]) == 2
    for name, texels in atlas_texels.items():
        assert np.array_equal(read_pixels(bpy.data.images[name]), texels)


def test_bad_texture_input_is_refused_with_a_clear_message_and_nothing_changes():
    tree = segmented_tree("Plain tree")
    bpy.context.view_layer.objects.active = tree
    assert bpy.ops.worldpaint.decompose_model(source='ATTRIBUTE', attribute="part") == {'FINISHED'}
    with pytest.raises(RuntimeError, match="'Plain tree' has no base texture"):
        bpy.ops.worldpaint.add_texture_edit()
    assert not tree.worldpaint_variety.texture_edits

    tree, base = textured_tree()
    bpy.context.view_layer.objects.active = tree
    assert bpy.ops.worldpaint.decompose_model(source='ATTRIBUTE', attribute="part") == {'FINISHED'}
    settings = tree.worldpaint_variety
    # an edit of another size
    small = bpy.data.images.new("Small edit", 32, 32)
    images_before = len(bpy.data.images)
    settings.texture_edits.add().image = small
    with pytest.raises(RuntimeError, match="'Small edit' is 32×32 pixels but the base texture 'Tree texture' is 48×48"):
        bpy.ops.worldpaint.generate_variants(count=5)
    assert settings.generated is None and not settings.atlases and len(bpy.data.images) == images_before
    # an edit where nothing was painted
    settings.texture_edits.clear()
    assert bpy.ops.worldpaint.add_texture_edit() == {'FINISHED'}
    with pytest.raises(RuntimeError, match="'Tree texture edit 1': it does not differ from the base texture"):
        bpy.ops.worldpaint.generate_variants(count=5)
    assert settings.generated is None and not settings.atlases
    # no UV map
    tree.data.uv_layers.remove(tree.data.uv_layers[0])
    with pytest.raises(RuntimeError, match="'Painted tree' has no UV map"):
        bpy.ops.worldpaint.generate_variants(count=5)
    assert settings.generated is None and not settings.atlases
    assert bpy.ops.worldpaint.remove_texture_edit() == {'FINISHED'} and not settings.texture_edits
    with pytest.raises(RuntimeError, match="no texture edit 1"):
        bpy.ops.worldpaint.remove_texture_edit()
