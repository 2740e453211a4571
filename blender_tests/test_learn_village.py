"""Learn Village inside Blender, on a real village of an imported place (``shared/data/real`` beside the project,
skipped with a message where absent), and its bad selections on a scene of the test's own.

Encamp (Andorra) is imported through File › Import › WorldPaint Place; a closed curve around it is the Village
panel's region; Learn Village (headless, a short search) adds a type "like Encamp" to an encyclopedia the .blend
keeps, sets the growth scenario to grow the real count of buildings with it, and Generate Village grows it on the
first click. The learned encyclopedia survives save and reload and exports to JSON. A search stopped early keeps its
best type. A region with too few buildings, none on the terrain, or without roads is refused with a message naming
what is wrong, and the scene is left as it was.
"""

import json

import bpy
import numpy as np
import pytest
from scene_kit import flat_terrain, poly_curve
from test_place_import import operator_import, real_files
from worldpaint.bridge import engine, engine_place, place, terrain, village
from worldpaint_engine import _engine

SIDE = 1000.0  # the region around the village: a square this wide (m), as the engine's real-village tests take


def encamp():
    """Imports Andorra; the square region curve around Encamp (the Village panel's region)."""
    layers, dem = real_files("andorra")
    operator_import(layers, dem)
    scene = bpy.context.scene
    named = engine_place.import_place([str(layers[3])], origin=place.place_origin(scene)).places
    centre = named.position[named.name.index("Encamp")]
    half = 0.5 * SIDE
    corners = [(centre[0] + x, centre[1] + y) for x, y in ((-half, -half), (half, -half), (half, half), (-half, half))]
    region = poly_curve("Encamp", corners, cyclic=True)
    scene.worldpaint.village.region = region
    return region


def test_learn_village_adds_a_type_like_encamp_that_grows_on_the_first_click(tmp_path):
    encamp()
    scene = bpy.context.scene
    settings = scene.worldpaint.village
    # one generation after the base: the time left for it, the finalists and the orientation step is judged at the
    # base's pace, slower than a generation's (three villages in parallel, not 42)
    result = bpy.ops.worldpaint.learn_village(minutes=3.0, max_evaluations=15)
    assert result == {'FINISHED'}
    print(settings.learn_report)
    assert settings.encyclopedia_text is not None
    learned = json.loads(settings.encyclopedia_text.as_string())
    assert "like Encamp" in learned["village_types"]
    assert "like Encamp" in village.known_types(settings)[0]
    events = [(e.kind, e.village_type if e.kind == 'VILLAGE_TYPE' else e.building, e.count) for e in settings.events]
    assert events[0][:2] == ('VILLAGE_TYPE', "like Encamp")
    asked = sum(count for kind, _, count in events if kind == 'GENERATE')
    real = int(settings.learn_report.split(" learned from ")[1].split()[0])
    assert real >= 50 and 0.8 * real <= asked <= 2.0 * real
    assert "bands from the real ones" in settings.learn_report
    # nearer the real village than the type it started from
    learned_bands = float(settings.learn_report.split("figures ")[1].split()[0])
    start_bands = float(settings.learn_report.split("(start ")[1].split(")")[0])
    assert learned_bands < start_bands
    # started from the shipped type whose villages come nearest Encamp's
    start = settings.learn_report.split("starting from '")[1].split("'")[0]
    assert start in json.loads(_engine.default_encyclopedia())["village_types"]

    assert bpy.ops.worldpaint.generate_village() == {'FINISHED'}
    houses = village.village_houses(settings.collection)
    assert len(houses) >= 0.6 * real
    assert {h[village.VILLAGE_TYPE_PROP] for h in houses} == {"like Encamp"}

    # kept with the .blend, exported as JSON
    path = tmp_path / "encamp.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.open_mainfile(filepath=str(path))
    settings = bpy.context.scene.worldpaint.village
    assert "like Encamp" in village.known_types(settings)[0]
    exported = tmp_path / "encyclopedia.json"
    assert bpy.ops.worldpaint.export_encyclopedia(filepath=str(exported)) == {'FINISHED'}
    assert "like Encamp" in engine.encyclopedia(exported.read_text()).village_types


def test_a_search_stopped_early_keeps_its_best_type():
    region = encamp()
    heightfield = terrain.engine_terrain(bpy.context, terrain.terrain_object(bpy.context))
    area = village.village_region(region, heightfield)
    centres, orientations, roads = place.real_village(bpy.context.scene, area)
    calls = []

    def stop_soon(fraction):
        calls.append(fraction)
        return len(calls) < 3

    result = engine.learn_village(heightfield, area, centres, orientations, roads, name="stopped",
                                  base_type="highland", max_seconds=300.0, progress=stop_soon)
    assert result["stopped_early"]
    assert "stopped" in engine.encyclopedia(result["encyclopedia"]).village_types
    assert result["evaluations"] < 200


def scene_state():
    scene = bpy.context.scene
    return (sorted(o.name for o in scene.objects), sorted(t.name for t in bpy.data.texts),
            scene.worldpaint.village.encyclopedia_text, len(scene.worldpaint.village.events))


def bad_selection(region_points, houses, roads=()):
    """A flat terrain 300 x 200 m with ``houses`` (XY) as a place's house cloud and ``roads`` as its residential
    streets; the Village panel's region the closed curve through ``region_points``."""
    scene = bpy.context.scene
    scene.worldpaint.terrain = flat_terrain("Flat", size=(300.0, 200.0))
    cloud = bpy.data.objects.new("WP_House", bpy.data.meshes.new("WP_House"))
    cloud["wp_points"] = "House"
    scene.collection.objects.link(cloud)
    xy = np.asarray(houses, dtype=np.float64).reshape(-1, 2)
    cloud.data.vertices.add(len(xy))
    cloud.data.vertices.foreach_set("co", np.column_stack([xy, np.zeros(len(xy))]).ravel())
    for k, line in enumerate(roads):
        street = poly_curve(f"Street {k}", line)
        street["wp_structure"] = "Residential street"
    scene.worldpaint.village.region = poly_curve("Selection", region_points, cyclic=True)


@pytest.mark.parametrize("case, message", [
    ("few", "holds 3 buildings"),
    ("no roads", "has no road"),
    ("off", "off the terrain"),
])
def test_bad_selections_are_refused_with_a_clear_message_and_change_nothing(case, message):
    square = [(20.0, 20.0), (120.0, 20.0), (120.0, 120.0), (20.0, 120.0)]
    houses = [(30.0 + 12.0 * k, 60.0 + 8.0 * (k % 2)) for k in range(8)]
    street = [[(10.0, 50.0), (140.0, 50.0)]]
    if case == "few":
        bad_selection(square, houses[:3], street)
    elif case == "no roads":
        bad_selection(square, houses)
    else:
        # reaching past the terrain's east edge (x = 300)
        bad_selection([(20.0, 20.0), (400.0, 20.0), (400.0, 150.0), (20.0, 150.0)], houses, street)
    before = scene_state()
    with pytest.raises(RuntimeError, match=message):
        bpy.ops.worldpaint.learn_village(minutes=0.2, max_evaluations=4)
    assert scene_state() == before


def test_a_village_types_own_footprint_sizes_are_read_and_checked():
    enc = json.loads(_engine.default_encyclopedia())
    house = enc["village_types"]["highland"]["buildings"]["house"]
    house["footprint"] = {"min": [7.0, 5.0], "max": [12.0, 8.0]}
    assert "highland" in engine.encyclopedia(json.dumps(enc)).village_types
    house["footprint"] = {"min": [7.0, 5.0], "max": [6.0, 8.0]}
    with pytest.raises(engine.engine_error(), match="footprint"):
        engine.encyclopedia(json.dumps(enc))
