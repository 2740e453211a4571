"""Arrangements as a user makes them: cobbles placed by hand are learned as a pattern, pasted along a path, sprayed
with the brush, erased, kept through save and reload, and pasted again; guides stop and orient the pattern."""

import math
import re

import bpy
import numpy as np
import pytest
from scene_kit import cobble_reference, flat_terrain, poly_curve, select_only
from worldpaint.bridge import arrangement, engine
from worldpaint.bridge.instances import point_cloud_arrays, point_cloud_objects, point_cloud_tints

SPACING = 1.0
DENSITY = 1.0 / (SPACING * SPACING * math.sqrt(3.0) / 2.0)  # a hexagonal lattice's elements per m²
REFERENCE = {"region_mode": 'RECT', "rect_min": (9.5, 9.5), "rect_max": (17.5, 15.8)}


def stroke(points):
    return [{"name": "", "location": (float(x), float(y), 0.0)} for x, y in points]


def learn_cobbles():
    terrain_obj = flat_terrain(size=(120.0, 120.0), cell=2.0)
    bpy.context.scene.worldpaint.terrain = terrain_obj
    examples = cobble_reference()
    select_only(examples)
    assert bpy.ops.worldpaint.learn_arrangement(name="Cobbles", **REFERENCE) == {'FINISHED'}
    select_only([])
    return terrain_obj, examples


def cobbles():
    """(co (N, 3), rotation, scale, prototype) of the painted cobbles."""
    clouds = point_cloud_objects(bpy.context.scene)
    return point_cloud_arrays(clouds["Cobble"]) if "Cobble" in clouds else (np.zeros((0, 3)),) * 4


def nearest(xy):
    d = np.hypot(*(xy[:, None, :] - xy[None, :, :]).transpose(2, 0, 1))
    np.fill_diagonal(d, np.inf)
    return d.min(axis=1)


def band_polygon(path, half_width):
    """A closed polygon around a polyline: its left side out, its right side back."""
    path = np.asarray(path, dtype=np.float64)
    tangent = np.gradient(path, axis=0)
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]]) / np.linalg.norm(tangent, axis=1)[:, None]
    return np.vstack([path + half_width * normal, (path - half_width * normal)[::-1]])


def test_learn_arrangement_makes_a_pattern_color_with_its_connectivity():
    learn_cobbles()
    settings = bpy.context.scene.worldpaint
    color = settings.palette["Cobbles"]
    summary = engine.arrangement_summary(color.json)
    assert len(summary.symbols) == 49 and len(summary.edges) >= 100, summary
    assert color.pattern_line.startswith("49 reference elements")
    assert settings.categories["Cobble"].kind == "arrangement"
    pixels = np.empty(64 * 64 * 4, dtype=np.float32)
    bpy.data.images[color.preview_image].pixels.foreach_get(pixels)
    grey = np.all(np.abs(pixels.reshape(-1, 4)[:, :3] - (0.45, 0.47, 0.45)) < 0.01, axis=1)
    assert grey.sum() > 100, "the preview draws the connectivity's edges"


def hand_placed_cobbles(turn_degrees=17.0, noise=0.03, seed=5):
    """Cobbles placed by hand on a hexagonal lattice turned by ``turn_degrees``, each off by a normal offset of
    ``noise`` spacings, about (13, 13) at z = 0; returns the example objects."""
    from scene_kit import collection_instances, stone_prototypes

    stone_prototypes()
    rng = np.random.default_rng(seed)
    row, col = np.divmod(np.arange(49), 7)
    xy = np.column_stack([col + 0.5 * (row % 2), row * math.sqrt(3.0) / 2.0]) * SPACING
    xy -= xy.mean(axis=0)
    c, s = math.cos(math.radians(turn_degrees)), math.sin(math.radians(turn_degrees))
    xy = xy @ np.array([[c, s], [-s, c]]) + (13.0, 13.0) + rng.normal(0.0, noise * SPACING, xy.shape)
    return collection_instances("Cobble", xy, np.zeros(len(xy)))


def test_cobbles_placed_by_hand_learn_without_a_terrain_and_paste_as_a_lattice(capfd):
    examples = hand_placed_cobbles()
    select_only(examples)
    assert bpy.context.scene.worldpaint.terrain is None
    assert bpy.ops.worldpaint.learn_arrangement(name="Cobbles", region_mode='RECT', rect_min=(8.0, 8.0),
                                                rect_max=(18.0, 18.0)) == {'FINISHED'}, "flat ground"
    select_only([])
    out = capfd.readouterr().out
    assert "Learned 'Cobbles': 49 reference elements" in out and "hexagonal lattice" in out, out
    bpy.context.scene.worldpaint.terrain = flat_terrain(size=(120.0, 120.0), cell=2.0)
    # 30 m x 30 m: about 26 times the reference's 34 m²
    assert bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(50.0, 50.0), rect_max=(80.0, 80.0),
                                          seed=1) == {'FINISHED'}
    out = capfd.readouterr().out
    line = next(line for line in out.splitlines() if "What the region holds now" in line)
    print(line)
    assert "pcf" not in line, "an arrangement is judged by its rings, not by a pcf"
    kept, interior, own = (float(x) for x in re.search(
        r"reference's for (\d+)% of (\d+) interior elements \(the reference's own (\d+)%\)", line).groups())
    assert interior > 500 and kept >= 0.95 * own, line
    co = cobbles()[0]
    assert abs(len(co) / (900.0 * DENSITY) - 1.0) < 0.1, f"{len(co)} cobbles"
    count_ratio = float(re.search(r"×([\d.]+) the reference's density", line).group(1))
    assert abs(count_ratio - len(co) / (900.0 * DENSITY)) < 0.05
    gaps = nearest(co[:, :2])
    assert np.abs(gaps / SPACING - 1.0).max() < 0.05, "every cobble a spacing from its nearest"


def test_a_pattern_pasted_along_a_path_brushed_erased_saved_and_pasted_again(tmp_path):
    learn_cobbles()
    path = [(30.0, 40.0), (50.0, 45.0), (70.0, 60.0), (85.0, 85.0)]
    t = np.linspace(0.0, 3.0, 31)
    centre = np.column_stack([np.interp(t, range(4), [p[i] for p in path]) for i in (0, 1)])
    outline = band_polygon(centre, 4.0)
    poly_curve("Path", [(x, y, 0.0) for x, y in outline], cyclic=True)
    x, y = outline[:, 0], outline[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    assert bpy.ops.worldpaint.paste_color(region_mode='CURVE', curve="Path", seed=1) == {'FINISHED'}
    co = cobbles()[0]
    gaps = nearest(co[:, :2])
    print(f"pasted {len(co)} cobbles along the path, {area * DENSITY:.0f} expected; nearest neighbour "
          f"{gaps.mean():.3f} m mean, {gaps.min():.3f} m closest")
    assert abs(len(co) / (area * DENSITY) - 1.0) < 0.12
    assert abs(gaps.mean() / SPACING - 1.0) < 0.06 and gaps.min() > 0.45 * SPACING
    depsgraph = bpy.context.evaluated_depsgraph_get()
    instanced = sum(1 for i in depsgraph.object_instances if i.is_instance and i.parent is not None
                    and i.parent.original.get("wp_points") == "Cobble")
    assert instanced == len(co), "every element is a Geometry Nodes instance"

    before = len(co)
    assert bpy.ops.worldpaint.brush(stroke=stroke([(20.0, 80.0), (35.0, 80.0)]), radius=3.0, seed=2) == {'FINISHED'}
    sprayed = cobbles()[0]
    new = sprayed[before:, :2]
    assert len(sprayed) - before > 0.7 * (15.0 * 6.0) * DENSITY, f"{len(sprayed) - before} sprayed"
    assert nearest(sprayed[:, :2]).min() > 0.45 * SPACING
    assert (np.abs(new[:, 1] - 80.0) <= 3.0 + 1e-6).all()

    assert bpy.ops.worldpaint.erase(stroke=stroke([(25.0, 80.0), (30.0, 80.0)]), radius=2.0) == {'FINISHED'}
    erased = cobbles()[0]
    x, y = sprayed[:, 0], sprayed[:, 1]
    under = np.hypot(x - np.clip(x, 25.0, 30.0), y - 80.0) <= 2.0
    assert len(sprayed) - len(erased) == under.sum() > 0, "the eraser removes the elements under it, no other"

    blend = str(tmp_path / "cobbles.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    bpy.ops.wm.open_mainfile(filepath=blend)
    color = bpy.context.scene.worldpaint.palette["Cobbles"]
    assert color.pattern_line and engine.arrangement_summary(color.json) is not None
    assert len(cobbles()[0]) == len(erased)
    assert bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(90.0, 10.0), rect_max=(110.0, 30.0),
                                          seed=3) == {'FINISHED'}
    assert abs((len(cobbles()[0]) - len(erased)) / (400.0 * DENSITY) - 1.0) < 0.12


def top_view_render(path, center, size, resolution=96):
    """A Cycles render (CPU, few samples, lit by a white sky) of a square of side ``size`` m seen from straight above;
    returns its pixels as (rows from the bottom, columns, RGBA)."""
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Top", bpy.data.cameras.new("Top"))
    camera.data.type = 'ORTHO'
    camera.data.ortho_scale = size
    camera.location = (center[0], center[1], 30.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    world = scene.world or bpy.data.worlds.new("Sky")
    scene.world = world
    world.color = (1.0, 1.0, 1.0)
    if world.node_tree is not None:
        for node in world.node_tree.nodes:
            if node.bl_idname == 'ShaderNodeBackground':
                node.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    scene.render.engine = 'CYCLES'
    scene.cycles.device = 'CPU'
    scene.cycles.samples = 16
    scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(str(path))
    pixels = np.empty(resolution * resolution * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    return pixels.reshape(resolution, resolution, 4)


def test_color_noise_tints_each_cobble_and_the_render_shows_it(tmp_path):
    learn_cobbles()
    settings = bpy.context.scene.worldpaint
    assert bpy.ops.worldpaint.pattern_settings(color_noise=0.3) == {'FINISHED'}
    assert "color noise 0.30" in settings.palette["Cobbles"].pattern_line
    assert bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(40.0, 40.0), rect_max=(52.0, 52.0),
                                          seed=1) == {'FINISHED'}
    cloud = point_cloud_objects(bpy.context.scene)["Cobble"]
    tints = point_cloud_tints(cloud)
    print(f"color noise 0.3: {len(tints)} cobbles, tint standard deviation {np.std(tints):.3f}")
    assert 0.24 < np.std(tints) < 0.36 and np.abs(tints).max() <= 1.0

    assert bpy.ops.worldpaint.tint_materials() == {'FINISHED'}
    assert bpy.ops.worldpaint.tint_materials() == {'FINISHED'}
    material = bpy.data.materials["Cobble"]
    groups = [n for n in material.node_tree.nodes if n.bl_idname == 'ShaderNodeGroup']
    assert len(groups) == 1, "tinting twice puts one group in front of the base color"

    # the brightness of each cobble's top, seen from above, follows its tint
    co, *_ = point_cloud_arrays(cloud)
    pixels = top_view_render(tmp_path / "tinted.png", (46.0, 46.0), 12.0)
    column = np.round((co[:, 0] - 40.0) / 12.0 * 96 - 0.5).astype(int)
    row = np.round((co[:, 1] - 40.0) / 12.0 * 96 - 0.5).astype(int)
    inside = (column >= 1) & (column < 95) & (row >= 1) & (row < 95)
    brightness = np.array([pixels[r - 1:r + 2, c - 1:c + 2, :3].mean()
                           for r, c in zip(row[inside], column[inside], strict=True)])
    correlation = np.corrcoef(brightness, tints[inside])[0, 1]
    print(f"{inside.sum()} cobbles in the picture: correlation of their brightness with their tint {correlation:.2f}")
    assert correlation > 0.8

    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "tinted.blend"))
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "tinted.blend"))
    assert np.array_equal(point_cloud_tints(point_cloud_objects(bpy.context.scene)["Cobble"]), tints)
    assert bpy.ops.worldpaint.convert_to_objects(category="Cobble") == {'FINISHED'}
    converted = bpy.data.collections["WP_Cobble objects"].objects
    assert sorted(o.get("tint", 0.0) for o in converted) == pytest.approx(sorted(tints), abs=1e-6), \
        "each object keeps its tint for the material to read"


def test_pattern_settings_noise_and_a_flipped_edge_are_kept_in_the_color():
    learn_cobbles()
    settings = bpy.context.scene.worldpaint
    assert bpy.ops.worldpaint.pattern_settings(rotation='BEST_FIT', scale_noise=0.1,
                                               rotation_noise=0.05) == {'FINISHED'}
    color = settings.palette["Cobbles"]
    assert "scale noise 0.10" in color.pattern_line
    assert bpy.ops.worldpaint.pattern_settings(relax_every=4) == {'FINISHED'}
    assert "scale noise 0.10" in color.pattern_line, "what a call does not set stays"
    assert bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(40.0, 40.0), rect_max=(60.0, 60.0),
                                          seed=1) == {'FINISHED'}
    _, _, scale, _ = cobbles()
    assert 0.07 < np.std(scale) < 0.13, f"scale noise {np.std(scale):.3f}"

    edges = {tuple(e) for e in engine.arrangement_summary(color.json).edges}
    boundary = engine.arrangement_summary(color.json).boundary
    a, b = next(e for e in sorted(edges) if not boundary[e[0]] and not boundary[e[1]])
    assert bpy.ops.worldpaint.flip_pattern_edge(a=a, b=b) == {'FINISHED'}
    after = {tuple(e) for e in engine.arrangement_summary(color.json).edges}
    assert (a, b) not in after and len(after) == len(edges), "the diagonal turned, no edge lost"
    with pytest.raises(RuntimeError, match="edge"):
        bpy.ops.worldpaint.flip_pattern_edge(a=0, b=48)  # no edge joins the two corners
    assert {tuple(e) for e in engine.arrangement_summary(color.json).edges} == after, "the color is unchanged"


def test_boundary_curves_stop_the_pattern_and_flow_curves_orient_it():
    learn_cobbles()
    settings = bpy.context.scene.worldpaint
    walls = bpy.data.collections.new("Walls")
    bpy.context.scene.collection.children.link(walls)
    poly_curve("Wall", [(50.0, 35.0, 0.0), (50.0, 85.0, 0.0)], collection=walls)
    settings.pattern_boundaries = walls
    bpy.context.scene.cursor.location = (45.0, 60.0, 0.0)
    assert bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(40.0, 40.0), rect_max=(60.0, 80.0),
                                          start='CURSOR', seed=1) == {'FINISHED'}
    co = cobbles()[0]
    assert len(co) > 0.8 * 10.0 * 40.0 * DENSITY and (co[:, 0] < 50.0).all(), "nothing crosses the wall"

    flow = bpy.data.collections.new("Flow")
    bpy.context.scene.collection.children.link(flow)
    angle = math.radians(20.0)
    direction = np.array([math.cos(angle), math.sin(angle)])
    for k, offset in enumerate((-8.0, 8.0)):
        start = np.array([72.0, 22.0]) + offset * np.array([-direction[1], direction[0]]) - 15.0 * direction
        end = start + 30.0 * direction
        poly_curve(f"Stream {k}", [(*start, 0.0), (*end, 0.0)], collection=flow)
    settings.pattern_flow = flow
    assert bpy.ops.worldpaint.pattern_settings(rotation='FLOW') == {'FINISHED'}
    assert bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(65.0, 15.0), rect_max=(79.0, 29.0),
                                          boundaries="", seed=2) == {'FINISHED'}
    co, rotation, _, _ = cobbles()
    new = co[:, 0] > 64.0
    # a hexagonal pattern looks the same turned by 60°
    off = np.abs((rotation[new] - angle + math.pi / 6.0) % (math.pi / 3.0) - math.pi / 6.0)
    print(f"flow: {new.sum()} cobbles, mean angle to the flow {np.degrees(off.mean()):.1f}°")
    assert new.sum() > 0.8 * 14.0 * 14.0 * DENSITY and np.degrees(off.mean()) < 5.0


def test_the_viewport_overlay_picks_the_edge_clicked_on():
    terrain_obj, _ = learn_cobbles()
    color = bpy.context.scene.worldpaint.palette["Cobbles"]
    overlay = arrangement.ReferenceOverlay(color.json, terrain_obj)
    try:
        assert len(overlay.edges) == len(engine.arrangement_summary(color.json).edges)
        assert np.abs(overlay.xyz[:, 2] - arrangement.LIFT).max() < 1e-6, "drawn on the flat ground"
        for a, b in overlay.edges[::7]:
            middle = 0.5 * (overlay.xy[a] + overlay.xy[b])
            assert overlay.edge_near(middle + 0.05) in {(a, b)}, "a click beside an edge's middle picks it"
        assert overlay.edge_near((60.0, 60.0)) is None, "a click far from the reference picks nothing"
    finally:
        overlay.remove()


def test_move_carries_the_pattern_rigidly_and_clear_removes_it():
    learn_cobbles()
    assert bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(40.0, 40.0), rect_max=(55.0, 55.0),
                                          seed=1) == {'FINISHED'}
    before = cobbles()[0][:, :2]
    assert bpy.ops.worldpaint.move_region(region_mode='RECT', rect_min=(40.0, 40.0), rect_max=(55.0, 55.0),
                                          offset=(30.0, 10.0)) == {'FINISHED'}
    after = cobbles()[0][:, :2]
    assert len(after) == len(before)
    moved = np.sort((before + (30.0, 10.0)).view(np.complex128).ravel())
    assert np.abs(np.sort(after.view(np.complex128).ravel()) - moved).max() < 1e-3, "the pattern moved as a whole"
    assert bpy.ops.worldpaint.clear_region(region_mode='RECT', rect_min=(60.0, 40.0), rect_max=(90.0, 70.0),
                                           category="Cobble") == {'FINISHED'}
    assert len(cobbles()[0]) == 0


def test_bad_input_is_refused_with_a_clear_message():
    learn_cobbles()
    with pytest.raises(RuntimeError, match="Nothing to learn"):
        bpy.ops.worldpaint.learn_arrangement(**REFERENCE)
    json_before = bpy.context.scene.worldpaint.palette["Cobbles"].json
    for noise in ({"rotation_noise": float("inf")}, {"scale_noise": 5.0}, {"color_noise": float("inf")}):
        name = next(iter(noise))
        # an infinity typed in Blender (stored as 3.4e38) is refused as not finite, a 5 as past the range
        with pytest.raises(RuntimeError, match=f"(?i){name.replace('_', '[ _]')} must be (between 0 and|a finite)"):
            bpy.ops.worldpaint.pattern_settings(**noise)
    assert bpy.context.scene.worldpaint.palette["Cobbles"].json == json_before, "the color is as it was"
    assert bpy.ops.worldpaint.pattern_settings(rotation='FLOW') == {'FINISHED'}
    with pytest.raises(RuntimeError, match="flow field"):
        bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(40.0, 40.0), rect_max=(50.0, 50.0))
    assert len(cobbles()[0]) == 0, "nothing was painted"
    with pytest.raises(RuntimeError, match="No collection 'Nowhere'"):
        bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(40.0, 40.0), rect_max=(50.0, 50.0),
                                       flow="Nowhere")
