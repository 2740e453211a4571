"""The palette's pictures of a color: its preview (the exemplar's points drawn as dots, one hue per category) and its
fidelity plot (drawn by the engine: the example's pcf and slope histograms beside those of the color's
self-synthesis, in the same hues). Both are packed images, saved in the .blend."""

import bpy
import numpy as np

from . import engine

SIZE = 64
BACKGROUND = (0.08, 0.09, 0.08, 1.0)
HUES = np.array(
    [
        (0.15, 0.55, 0.15, 1.0),  # green
        (0.60, 0.58, 0.55, 1.0),  # grey
        (0.75, 0.85, 0.25, 1.0),  # yellow-green
        (0.80, 0.45, 0.20, 1.0),  # orange
        (0.30, 0.50, 0.85, 1.0),  # blue
        (0.75, 0.30, 0.60, 1.0),  # purple
    ],
    dtype=np.float32,
)
HUE_NAMES = ("green", "grey", "yellow-green", "orange", "blue", "purple")


def hue_legend(category_names, figures=None):
    """Which hue stands for which category in a color's preview and fidelity plot, with the category's figure when
    ``figures`` ({name: value}) has one: "green Tree 0.42, grey Rock"."""
    figures = figures or {}

    def item(i, name):
        figure = f" {figures[name]:.2f}" if name in figures else ""
        return f"{HUE_NAMES[i % len(HUE_NAMES)]} {name}{figure}"

    return ", ".join(item(i, name) for i, name in enumerate(category_names))


def preview_pixels(summary, size=SIZE):
    """RGBA float32 pixels (size * size * 4, bottom row first) of a color's preview points (``engine.ColorSummary``)."""
    pixels = np.empty((size, size, 4), dtype=np.float32)
    pixels[:] = BACKGROUND
    pts = np.asarray(summary.preview, dtype=np.float64).reshape(-1, 3)
    width, height = summary.preview_size
    extent = max(width, height, 1e-9)
    if len(pts):
        px = np.clip((pts[:, 0] / extent * (size - 2)).astype(int), 0, size - 2)
        py = np.clip((pts[:, 1] / extent * (size - 2)).astype(int), 0, size - 2)
        hue = HUES[pts[:, 2].astype(int) % len(HUES)]
        # 2x2 dots; later categories (lower priority, e.g. grass) are drawn under the earlier ones
        order = np.argsort(-pts[:, 2], kind="stable")
        for dy in (0, 1):
            for dx in (0, 1):
                pixels[py[order] + dy, px[order] + dx] = hue[order]
    return pixels.ravel()


EDGE = (0.45, 0.47, 0.45, 1.0)


def draw_edges(pixels, summary, pattern, size=SIZE):
    """Draws an arrangement's connectivity (``engine.ArrangementSummary``) as grey lines under the preview's dots."""
    width, height = summary.preview_size
    extent = max(width, height, 1e-9)
    grid = pixels.reshape(size, size, 4)
    ends = pattern.positions[pattern.edges] / extent * (size - 2) + 0.5  # (E, 2, 2) pixel coordinates
    t = np.linspace(0.0, 1.0, 2 * size)[None, :, None]
    samples = (ends[:, :1] * (1.0 - t) + ends[:, 1:] * t).reshape(-1, 2).astype(int)
    samples = np.clip(samples, 0, size - 1)
    grid[samples[:, 1], samples[:, 0]] = EDGE


def make_preview(color_json, name):
    """A packed 64x64 image of the color's exemplar (an arrangement's with its connectivity); returns its name."""
    summary = engine.color_summary(color_json)
    pattern = engine.arrangement_summary(color_json)
    if pattern is None:
        pixels = preview_pixels(summary)
    else:
        pixels = np.empty((SIZE, SIZE, 4), dtype=np.float32)
        pixels[:] = BACKGROUND
        if len(pattern.edges):
            draw_edges(pixels, summary, pattern)
        dots = preview_pixels(summary).reshape(SIZE, SIZE, 4)
        drawn = np.any(dots != np.asarray(BACKGROUND, dtype=np.float32), axis=2)
        pixels[drawn] = dots[drawn]
        pixels = pixels.ravel()
    return packed_image(f"WP preview {name}", pixels, SIZE, SIZE)


def packed_image(name, pixels, width, height):
    """A new packed image of float32 RGBA ``pixels`` (bottom row first), kept with a fake user; returns its name."""
    image = bpy.data.images.new(name, width, height, alpha=True)
    image.pixels.foreach_set(np.ascontiguousarray(pixels, dtype=np.float32).ravel())
    image.pack()
    image.use_fake_user = True
    return image.name


def make_fidelity_image(rgba, name):
    """A packed image of a color's fidelity plot (uint8 (height, width, 4), rows from the top); returns its name."""
    height, width = rgba.shape[:2]
    pixels = np.flipud(np.asarray(rgba, dtype=np.float32) / 255.0)
    return packed_image(f"WP fidelity {name}", pixels, width, height)


def copy_image(image_name, name_stem):
    """A packed copy of an image, named ``name_stem`` (numbered by Blender when taken); "" when there is none."""
    image = bpy.data.images.get(image_name)
    if image is None:
        return ""
    width, height = image.size
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    return packed_image(name_stem, pixels, width, height)


def remove_preview(image_name):
    image = bpy.data.images.get(image_name)
    if image is not None:
        bpy.data.images.remove(image)


def remove_pictures(entry):
    """Removes a palette color's preview and fidelity plot."""
    remove_preview(entry.preview_image)
    remove_preview(entry.fidelity_image)
