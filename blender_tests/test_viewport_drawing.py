"""The brush circle that the Brush, Eraser and Pipette tools draw over the viewport is drawn by the GPU module of
every Blender the suite runs on. Blender 5.x draws offscreen in background mode once ``gpu.init()`` has run; 4.5 as
a Python module cannot draw in background mode at all, so there the test is skipped."""

import json
import pathlib
import subprocess
import sys

import gpu
import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
SIZE, CENTER, RADIUS, WIDTH = 200, 100.0, 60.0, 4.0

# runs in its own Blender process, so the GPU context it makes stays out of the rest of the suite
DRAW_CIRCLE = f"""
import json, math, sys
import bpy, gpu
import numpy as np
from mathutils import Matrix
sys.path.insert(0, sys.argv[1])
from worldpaint.bridge import view

gpu.init()
offscreen = gpu.types.GPUOffScreen({SIZE}, {SIZE})
circle = [({CENTER} + {RADIUS} * math.cos(2 * math.pi * k / 48), {CENTER} + {RADIUS} * math.sin(2 * math.pi * k / 48))
          for k in range(48)]
pixel_space = Matrix(((2 / {SIZE}, 0, 0, -1), (0, 2 / {SIZE}, 0, -1), (0, 0, 1, 0), (0, 0, 0, 1)))
with offscreen.bind():
    framebuffer = gpu.state.active_framebuffer_get()
    framebuffer.clear(color=(0.0, 0.0, 0.0, 0.0))
    with gpu.matrix.push_pop(), gpu.matrix.push_pop_projection():
        gpu.matrix.load_matrix(Matrix.Identity(4))
        gpu.matrix.load_projection_matrix(pixel_space)
        view.draw_line_loop(circle, ({SIZE}, {SIZE}), (1.0, 1.0, 1.0, 1.0), {WIDTH})
    rgba = framebuffer.read_color(0, 0, {SIZE}, {SIZE}, 4, 0, 'UBYTE').to_list()
offscreen.free()
lit = np.nonzero(np.array(rgba, dtype=np.uint8).reshape({SIZE}, {SIZE}, 4)[..., 0] > 128)
print("RESULT " + json.dumps([[int(y), int(x)] for y, x in zip(*lit)]))
"""


@pytest.mark.skipif(not hasattr(gpu, "init"), reason="this Blender cannot draw in background mode (no gpu.init)")
def test_the_brush_circle_is_drawn_as_a_ring_of_its_radius_and_width():
    run = subprocess.run([sys.executable, "-c", DRAW_CIRCLE, str(ROOT / "addon")], capture_output=True, text=True,
                         timeout=300)
    lines = [line for line in run.stdout.splitlines() if line.startswith("RESULT ")]
    assert lines, run.stdout[-2000:] + run.stderr[-2000:]
    lit = np.array(json.loads(lines[-1][len("RESULT "):]), dtype=float).reshape(-1, 2)
    r = np.hypot(lit[:, 0] + 0.5 - CENTER, lit[:, 1] + 0.5 - CENTER)
    ring = 2.0 * np.pi * RADIUS * WIDTH
    assert 0.8 * ring < len(lit) < 1.2 * ring, f"{len(lit)} pixels lit for a ring of {ring:.0f}"
    assert abs(r.min() - (RADIUS - WIDTH / 2)) < 1.5 and abs(r.max() - (RADIUS + WIDTH / 2)) < 1.5, (r.min(), r.max())
