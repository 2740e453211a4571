"""The fidelity view: after Learn Color the palette shows how well the color reproduces its example (the pcf and slope
histograms of the example beside those of the color painted into the example's region, and a one-line figure), and
Paste reports the same figure for what it painted."""

import math
import os
import struct
import time
import zlib

import bpy
import numpy as np
import pytest
from scene_kit import select_only, slope_exemplar
from worldpaint.ops.colors import FIDELITY_SIZE

EXEMPLAR = {"region_mode": 'RECT', "rect_min": (0.0, 0.0), "rect_max": (100.0, 100.0)}
DESTINATION = {"region_mode": 'RECT', "rect_min": (0.0, 100.0), "rect_max": (200.0, 200.0)}


def learn_slope_color(name="Slope forest"):
    terrain_obj, examples, data = slope_exemplar()
    select_only(examples)
    started = time.perf_counter()
    assert bpy.ops.worldpaint.learn_color(name=name, **EXEMPLAR) == {'FINISHED'}
    print(f"Learn Color with its fidelity view: {time.perf_counter() - started:.2f} s")
    return terrain_obj, examples, data


def plot_pixels(entry):
    """The fidelity plot of a palette entry as float RGBA (height, width, 4), bottom row first."""
    image = bpy.data.images[entry.fidelity_image]
    width, height = image.size
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    return pixels.reshape(height, width, 4)


def keep_png(pixels, name):
    """Writes the plot as a PNG under ``WORLDPAINT_PLOT_DIR`` when it is set, to look at it."""
    folder = os.environ.get("WORLDPAINT_PLOT_DIR")
    if not folder:
        return
    rgb = (np.flipud(pixels[:, :, :3]) * 255.0 + 0.5).astype(np.uint8)
    height, width = rgb.shape[:2]
    raw = b"".join(b"\x00" + row.tobytes() for row in rgb)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
    with open(os.path.join(folder, f"{name}.png"), "wb") as f:
        f.write(png)


def assert_shows_a_plot(entry):
    image = bpy.data.images.get(entry.fidelity_image)
    assert image is not None and image.packed_file is not None, "the plot is a packed image"
    assert tuple(image.size) == FIDELITY_SIZE
    pixels = plot_pixels(entry)
    spread = pixels[:, :, :3].std(axis=(0, 1)).max()
    assert spread > 0.05, f"the plot is blank (pixel spread {spread:.3f})"
    return pixels


def test_learn_color_shows_the_fidelity_view_of_the_color():
    learn_slope_color()
    entry = bpy.context.scene.worldpaint.palette["Slope forest"]
    keep_png(assert_shows_a_plot(entry), "slope_forest")
    assert entry.fidelity_image == "WP fidelity Slope forest"
    # the slope forest's worst pair is rock-grass (about 20 rocks): its pcf is noisy, so the figure is a few units;
    # painted into its own region the color has its example's counts
    assert math.isfinite(entry.fidelity_rdf_l2) and 0.0 <= entry.fidelity_rdf_l2 < 20.0
    assert entry.fidelity_density == pytest.approx(1.0, abs=0.15)
    distance, pcf, slope = entry.fidelity_axes
    assert distance > 0.0 and pcf >= 2.0 and 10.0 < slope <= 92.5, "a pcf panel and a slope panel"
    # the preview's hues, by priority, each with the category's own pcf L2 (the worst is the figure)
    legend = [item.split() for item in entry.fidelity_legend.split(", ")]
    assert [(hue, name) for hue, name, _ in legend] == [("green", "Rock"), ("grey", "Tree"), ("yellow-green", "Grass")]
    assert max(float(figure) for *_, figure in legend) <= entry.fidelity_rdf_l2 + 0.005
    assert entry.fidelity_line().startswith(f"pcf L2 {entry.fidelity_rdf_l2:.2f} against the example (density ×")
    print(entry.fidelity_line(), "|", " | ".join(entry.fidelity_axes_lines()))


def test_the_same_example_gives_the_same_fidelity_view():
    _, examples, _ = learn_slope_color("First")
    select_only(examples)
    assert bpy.ops.worldpaint.learn_color(name="Second", **EXEMPLAR) == {'FINISHED'}
    first, second = bpy.context.scene.worldpaint.palette
    assert first.fidelity_rdf_l2 == second.fidelity_rdf_l2 and first.fidelity_density == second.fidelity_density
    np.testing.assert_array_equal(plot_pixels(first), plot_pixels(second))


def test_the_fidelity_view_survives_save_and_reload(tmp_path):
    learn_slope_color()
    entry = bpy.context.scene.worldpaint.palette[0]
    saved = (entry.fidelity_image, entry.fidelity_rdf_l2, entry.fidelity_density, *entry.fidelity_axes)
    pixels = plot_pixels(entry)
    path = str(tmp_path / "fidelity.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert bpy.data.images.get(saved[0]) is None
    bpy.ops.wm.open_mainfile(filepath=path)

    entry = bpy.context.scene.worldpaint.palette[0]
    assert entry.fidelity_image == saved[0]
    assert (entry.fidelity_rdf_l2, entry.fidelity_density, *entry.fidelity_axes) == pytest.approx(saved[1:])
    assert_shows_a_plot(entry)
    np.testing.assert_allclose(plot_pixels(entry), pixels, atol=1.0 / 255.0)


def test_paste_reports_the_figure_of_what_it_painted(capfd):
    learn_slope_color()
    select_only([])
    capfd.readouterr()
    assert bpy.ops.worldpaint.paste_color(seed=7, **DESTINATION) == {'FINISHED'}
    out = capfd.readouterr().out
    line = next((ln for ln in out.splitlines() if "What the region holds now: pcf L2 " in ln), None)
    assert line is not None, out
    figure = float(line.split("pcf L2 ")[1].split()[0])
    density = float(line.split("density ×")[1].rstrip(")"))
    print(line)
    assert math.isfinite(figure) and figure >= 0.0
    assert density == pytest.approx(1.0, abs=0.2), "the paste has about the example's density"


def test_the_fidelity_plot_follows_its_color_through_remove_duplicate_and_import(tmp_path):
    learn_slope_color()
    settings = bpy.context.scene.worldpaint
    assert bpy.ops.worldpaint.duplicate_color() == {'FINISHED'}
    original, copy = settings.palette
    assert copy.fidelity_image != original.fidelity_image and copy.fidelity_image.startswith("WP fidelity")
    assert copy.fidelity_rdf_l2 == original.fidelity_rdf_l2
    np.testing.assert_array_equal(plot_pixels(copy), plot_pixels(original))
    assert bpy.data.images[copy.fidelity_image].packed_file is not None

    # an imported color's terrain is not known: its view is of the color painted without terrain (no slope panel)
    path = str(tmp_path / "palette.json")
    assert bpy.ops.worldpaint.export_palette(filepath=path) == {'FINISHED'}
    assert bpy.ops.worldpaint.import_palette(filepath=path) == {'FINISHED'}
    imported = settings.palette[2]
    assert imported.fidelity_note == ""
    assert_shows_a_plot(imported)
    assert imported.fidelity_axes[2] == 0.0 and math.isfinite(imported.fidelity_rdf_l2)

    names = [entry.fidelity_image for entry in settings.palette]
    assert bpy.ops.worldpaint.remove_color(index=0) == {'FINISHED'}
    assert bpy.data.images.get(names[0]) is None, "the plot goes with its color"
    assert all(bpy.data.images.get(name) is not None for name in names[1:])
    assert bpy.ops.worldpaint.import_palette(filepath=path, replace=True) == {'FINISHED'}
    plots = sorted(image.name for image in bpy.data.images if image.name.startswith("WP fidelity"))
    assert plots == sorted(entry.fidelity_image for entry in settings.palette), "the replaced plots are gone"


def test_the_engine_draws_the_plot_at_the_size_asked_and_refuses_a_tiny_one():
    import worldpaint_engine as engine

    learn_slope_color()
    color_json = bpy.context.scene.worldpaint.palette[0].json
    view = engine.fidelity(color_json, None, 3, width=200, height=100)
    assert view["image"].shape == (100, 200, 4) and view["image"].dtype == np.uint8
    assert view["max_slope_degrees"] is None, "painted without terrain: no slope panel"
    assert set(view["density_ratio"]) == {"Tree", "Rock", "Grass"} and math.isfinite(view["max_rdf_l2"])
    with pytest.raises(engine.InputError, match="width"):
        engine.fidelity(color_json, None, 3, width=8, height=100)
