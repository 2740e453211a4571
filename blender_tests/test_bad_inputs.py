"""Bad inputs give a clear error from the operator and leave the scene as it was."""

import bpy
import pytest
from scene_kit import select_only, slope_exemplar
from worldpaint.bridge.instances import point_cloud_objects

EXEMPLAR = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (100.0, 100.0)}


def snapshot():
    scene = bpy.context.scene
    return (
        len(bpy.data.objects),
        len(bpy.data.collections),
        len(scene.worldpaint.palette),
        len(scene.worldpaint.categories),
        {c: len(o.data.vertices) for c, o in point_cloud_objects(scene).items()},
    )


@pytest.fixture
def learned():
    terrain_obj, examples, _ = slope_exemplar()
    select_only(examples)
    bpy.ops.worldpaint.learn_color(name="Slope forest", **EXEMPLAR)
    select_only([])
    bpy.ops.worldpaint.paste_color(seed=1, region_mode='RECT', rect_min=(100.0, 100.0), rect_max=(200.0, 200.0))
    return terrain_obj, examples


def test_no_terrain(learned):
    bpy.context.scene.worldpaint.terrain = None
    before = snapshot()
    with pytest.raises(RuntimeError, match="No terrain"):
        bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(0.0, 100.0), rect_max=(100.0, 200.0))
    with pytest.raises(RuntimeError, match="No terrain"):
        bpy.ops.worldpaint.learn_color(**EXEMPLAR)
    assert snapshot() == before


def test_terrain_that_is_not_a_mesh(learned):
    empty = bpy.data.objects.new("NotATerrain", None)
    bpy.context.scene.collection.objects.link(empty)
    before = snapshot()
    with pytest.raises(RuntimeError, match="not a mesh"):
        bpy.ops.worldpaint.paste_color(terrain="NotATerrain", **EXEMPLAR)
    assert snapshot() == before


def test_empty_selection(learned):
    select_only([])
    before = snapshot()
    with pytest.raises(RuntimeError, match="Nothing to learn: select the example objects"):
        bpy.ops.worldpaint.learn_color()
    with pytest.raises(RuntimeError, match="Select objects to define the region"):
        bpy.ops.worldpaint.paste_color(region_mode='SELECTION')
    assert snapshot() == before


def test_region_off_the_terrain(learned):
    before = snapshot()
    with pytest.raises(RuntimeError, match="lies outside the terrain"):
        bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(500.0, 500.0), rect_max=(600.0, 600.0))
    with pytest.raises(RuntimeError, match="lies outside the terrain"):
        bpy.ops.worldpaint.paste_color(region_mode='CIRCLE', circle_center=(-300.0, 0.0), circle_radius=50.0)
    assert snapshot() == before


def test_degenerate_region(learned):
    before = snapshot()
    with pytest.raises(RuntimeError, match="region"):
        bpy.ops.worldpaint.paste_color(region_mode='RECT', rect_min=(10.0, 10.0), rect_max=(10.0, 50.0))
    assert snapshot() == before


def test_open_curve_region(learned):
    from scene_kit import closed_circle_curve

    curve = closed_circle_curve("Open", (50.0, 50.0), 20.0)
    curve.data.splines[0].use_cyclic_u = False
    select_only([curve])
    before = snapshot()
    with pytest.raises(RuntimeError, match="not closed"):
        bpy.ops.worldpaint.paste_color(region_mode='CURVE')
    assert snapshot() == before


def test_empty_palette():
    terrain_obj, _, _ = slope_exemplar()
    before = snapshot()
    with pytest.raises(RuntimeError, match="palette is empty"):
        bpy.ops.worldpaint.paste_color(**EXEMPLAR)
    with pytest.raises(RuntimeError, match="palette is empty"):
        bpy.ops.worldpaint.export_palette(filepath="/nonexistent/never.json")
    assert snapshot() == before


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("this is not json {", "not a usable WorldPaint palette"),
        ('{"format": "worldpaint-palette", "version": 99, "colors": []}', "version 99"),
        ('{"format": "worldpaint-palette", "version": 1, "colors": [{"name": 3}]}', "not a usable"),
    ],
)
def test_corrupt_palette_file(learned, tmp_path, content, message):
    path = tmp_path / "bad.json"
    path.write_text(content)
    before = snapshot()
    with pytest.raises(RuntimeError, match=message):
        bpy.ops.worldpaint.import_palette(filepath=str(path))
    assert snapshot() == before


def test_missing_palette_file(learned, tmp_path):
    before = snapshot()
    with pytest.raises(RuntimeError, match="Cannot read the palette file"):
        bpy.ops.worldpaint.import_palette(filepath=str(tmp_path / "missing.json"))
    assert snapshot() == before


def test_unknown_color_and_category(learned):
    before = snapshot()
    with pytest.raises(RuntimeError, match="No color named 'Nope'"):
        bpy.ops.worldpaint.paste_color(color="Nope", **EXEMPLAR)
    with pytest.raises(RuntimeError, match="No synthesized instances of category 'Nope'"):
        bpy.ops.worldpaint.convert_to_objects(category="Nope")
    assert snapshot() == before


def data_counts():
    return {kind: len(getattr(bpy.data, kind)) for kind in ("collections", "objects", "meshes", "curves", "materials",
                                                             "node_groups")}


def test_a_paste_that_pastes_nothing_leaves_nothing_behind(capfd):
    _, examples, _ = slope_exemplar()
    select_only(examples)
    bpy.ops.worldpaint.learn_color(name="Slope forest", **EXEMPLAR)
    select_only([])
    before = data_counts()
    capfd.readouterr()
    # half a metre across: room for no instance of the color
    assert bpy.ops.worldpaint.paste_color(seed=1, region_mode='RECT', rect_min=(150.0, 150.0),
                                          rect_max=(150.5, 150.5)) == {'FINISHED'}
    assert "Warning: Nothing pasted for Grass, Rock, Tree" in capfd.readouterr().out
    assert data_counts() == before, "no empty point cloud, collection or instancer"
    assert not point_cloud_objects(bpy.context.scene)


def linked_tree_collection(tmp_path):
    """The collection "Tree" linked from a library .blend, beside the local one of the same name."""
    path = str(tmp_path / "library.blend")
    bpy.data.libraries.write(path, {bpy.data.collections["Tree"]}, fake_user=True)
    with bpy.data.libraries.load(path, link=True) as (_, target):
        target.collections = ["Tree"]
    return target.collections[0]


def instances_of(collection, positions):
    made = []
    for k, (x, y) in enumerate(positions):
        obj = bpy.data.objects.new(f"{collection.name} instance {k}", None)
        obj.instance_type, obj.instance_collection = 'COLLECTION', collection
        obj.location = (x, y, 0.0)
        bpy.context.scene.collection.objects.link(obj)
        made.append(obj)
    return made


def test_two_collections_of_one_name_are_refused(learned, tmp_path):
    _, examples = learned
    linked = linked_tree_collection(tmp_path)
    assert linked.library is not None and linked.name == "Tree"
    select_only(examples + instances_of(linked, [(20.0, 30.0), (60.0, 70.0)]))
    before = snapshot()
    clash = r"both category 'Tree' in the example: collection 'Tree' \(.*\) and collection 'Tree \[library.blend\]'"
    with pytest.raises(RuntimeError, match=clash):
        bpy.ops.worldpaint.learn_color(**EXEMPLAR)
    assert snapshot() == before


def test_a_mesh_and_a_collection_of_one_name_are_refused_unless_the_collection_holds_the_mesh(learned):
    _, examples = learned
    # a bush mesh placed by hand, and a collection "Bush" of something else
    bush = bpy.data.objects.new("Bush", bpy.data.meshes.new("Bush"))
    bpy.context.scene.collection.objects.link(bush)
    bush.location = (40.0, 40.0, 0.0)
    other = bpy.data.collections.new("Bush")
    other.objects.link(bpy.data.objects.new("Hedge", bpy.data.meshes.new("Hedge")))
    select_only(examples + [bush] + instances_of(other, [(45.0, 45.0)]))
    before = snapshot()
    with pytest.raises(RuntimeError, match="Two different things are both category 'Bush'.*mesh 'Bush'"):
        bpy.ops.worldpaint.learn_color(**EXEMPLAR)
    assert snapshot() == before
    # a mesh "Tree" held by the collection "Tree": a linked duplicate of it is a tree like the instances
    bpy.data.meshes["TreeMesh"].name = "Tree"
    tree = bpy.data.objects.new("Tree copy", bpy.data.meshes["Tree"])
    bpy.context.scene.collection.objects.link(tree)
    tree.location = (50.0, 50.0, 0.0)
    select_only(examples + [tree])
    assert bpy.ops.worldpaint.learn_color(name="With a copy", **EXEMPLAR) == {'FINISHED'}
    assert len(bpy.context.scene.worldpaint.categories) == before[3]


def test_a_category_of_objects_and_curves_is_refused(learned):
    from scene_kit import poly_curve

    _, examples = learned
    examples[0]["wp_category"] = "Path"
    path = poly_curve("Path", [(10.0, 10.0, 0.0), (90.0, 90.0, 0.0)])
    select_only(examples + [path])
    before = snapshot()
    with pytest.raises(RuntimeError, match=r"The category 'Path' is both objects \('.*'\) and open curves "
                                           r"\('Path'\)"):
        bpy.ops.worldpaint.learn_color(**EXEMPLAR)
    assert snapshot() == before


def test_a_palette_imported_twice_gets_numbered_names(learned, tmp_path):
    from worldpaint.bridge import engine

    path = str(tmp_path / "palette.json")
    assert bpy.ops.worldpaint.export_palette(filepath=path) == {'FINISHED'}
    assert bpy.ops.worldpaint.import_palette(filepath=path) == {'FINISHED'}
    assert bpy.ops.worldpaint.import_palette(filepath=path) == {'FINISHED'}
    palette = bpy.context.scene.worldpaint.palette
    names = [entry.name for entry in palette]
    assert names == ["Slope forest", "Slope forest.001", "Slope forest.002"]
    assert [engine.color_summary(entry.json).name for entry in palette] == names, "each color knows its name"
    # a file holding one name twice, replacing the palette
    assert bpy.ops.worldpaint.export_palette(filepath=path) == {'FINISHED'}
    palette[1].name = "Slope forest"
    assert bpy.ops.worldpaint.export_palette(filepath=path) == {'FINISHED'}
    assert bpy.ops.worldpaint.import_palette(filepath=path, replace=True) == {'FINISHED'}
    assert [entry.name for entry in palette] == ["Slope forest", "Slope forest.001", "Slope forest.002"]


def test_a_learned_color_under_a_taken_name_is_numbered(learned):
    _, examples = learned
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Slope forest", **EXEMPLAR) == {'FINISHED'}
    assert [entry.name for entry in bpy.context.scene.worldpaint.palette] == ["Slope forest", "Slope forest 2"]


def test_an_exported_palette_gets_its_extension(learned, tmp_path):
    assert bpy.ops.worldpaint.export_palette(filepath=str(tmp_path / "forest")) == {'FINISHED'}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["forest.json"]
    assert bpy.ops.worldpaint.import_palette(filepath=str(tmp_path / "forest.json")) == {'FINISHED'}
    before = snapshot()
    with pytest.raises(RuntimeError, match="No file name in the path"):
        bpy.ops.worldpaint.export_palette(filepath=str(tmp_path) + "/")
    assert snapshot() == before and sorted(p.name for p in tmp_path.iterdir()) == ["forest.json"]


def test_a_relative_path_needs_a_saved_file(learned, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # where a path relative to an unsaved file would have gone
    before = snapshot()
    saved_first = "is relative to the .blend file, which is not saved yet: save the file first or give an absolute path"
    with pytest.raises(RuntimeError, match=f"The palette file path '//forest.json' {saved_first}"):
        bpy.ops.worldpaint.export_palette(filepath="//forest.json")
    with pytest.raises(RuntimeError, match=f"The palette file path '//forest.json' {saved_first}"):
        bpy.ops.worldpaint.import_palette(filepath="//forest.json")
    with pytest.raises(RuntimeError, match=f"The encyclopedia file path '//buildings.json' {saved_first}"):
        bpy.ops.worldpaint.generate_village(encyclopedia_path="//buildings.json")
    with pytest.raises(RuntimeError, match=f"The scenario file path '//scenario.json' {saved_first}"):
        bpy.ops.worldpaint.generate_village(scenario_path="//scenario.json")
    bpy.context.scene.worldpaint.village.encyclopedia_path = "//buildings.json"
    with pytest.raises(RuntimeError, match=f"The encyclopedia file path '//buildings.json' {saved_first}"):
        bpy.ops.worldpaint.show_interest()
    bpy.context.scene.worldpaint.village.encyclopedia_path = ""
    assert snapshot() == before and not list(tmp_path.iterdir())
    # saved, the file's folder is where they go
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "forest.blend"))
    assert bpy.ops.worldpaint.export_palette(filepath="//forest.json") == {'FINISHED'}
    assert (tmp_path / "forest.json").exists()
    assert bpy.ops.worldpaint.import_palette(filepath="//forest.json") == {'FINISHED'}
