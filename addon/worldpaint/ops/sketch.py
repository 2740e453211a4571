"""Apply Sketch (thesis ch. 5): the terrain deformed so that, seen from the sketch camera, its silhouettes follow the
strokes drawn over the view and nothing hides them. The change is a shape key named after the operator, what stands
on the changed ground moves with it, and the run is one undo step with progress and Esc."""

import json

import bpy
import numpy as np
from bpy.props import BoolProperty, FloatProperty, StringProperty

from ..bridge import WorldPaintError, engine, sketch, sketch_strokes, terrain, terrain_edit
from .background import BackgroundOperator
from .common import TerrainProperty, setting
from .terrain_edit import UNMOVED, editable_terrain


def strokes_from_json(text):
    """Strokes given as JSON text: a list of strokes, each a list of [x, y] camera-frame points. A point must be two
    numbers (not booleans, not three coordinates); the frame itself is checked by the engine."""
    try:
        strokes = json.loads(text)
    except RecursionError:
        raise WorldPaintError("The strokes are not a JSON list of strokes of [x, y] points: they are nested too "
                              "deeply") from None
    except ValueError as exc:
        raise WorldPaintError(f"The strokes are not a JSON list of strokes of [x, y] points: {exc}") from None
    if not isinstance(strokes, list):
        raise WorldPaintError(f"The strokes are not a JSON list of strokes of [x, y] points: got a "
                              f"{type(strokes).__name__}")
    arrays = []
    for k, stroke in enumerate(strokes):
        if not isinstance(stroke, list):
            raise WorldPaintError(f"Stroke {k} is not a list of [x, y] points: got a {type(stroke).__name__}")
        for j, point in enumerate(stroke):
            if not isinstance(point, list) or len(point) != 2:
                shape = f"{len(point)} values" if isinstance(point, list) else f"a {type(point).__name__}"
                raise WorldPaintError(f"Stroke {k}, point {j} is not an [x, y] pair of numbers: got {shape}")
            for value in point:
                if isinstance(value, bool) or not isinstance(value, (int, float)):
                    raise WorldPaintError(f"Stroke {k}, point {j} is not an [x, y] pair of numbers: got "
                                          f"{json.dumps(value)}")
                if isinstance(value, int) and abs(value) > 1e300:
                    raise WorldPaintError(f"Stroke {k}, point {j} lies out of the camera frame: {value:.3g} (the "
                                          "frame runs from 0 to 1)")
        arrays.append(np.array(stroke, dtype=np.float64).reshape(-1, 2))
    return arrays


class WORLDPAINT_OT_apply_sketch(BackgroundOperator, TerrainProperty, bpy.types.Operator):
    """Deform the terrain so that, seen from the sketch camera, its silhouettes follow the sketched strokes and
    nothing hides them (a shape key; Esc cancels). Stroke points are in the camera frame: x from 0 (left) to 1
    (right), y from 0 (bottom) to 1 (top)"""

    bl_idname = "worldpaint.apply_sketch"
    bl_label = "Apply Sketch"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Applying sketch"

    camera: StringProperty(name="Camera", description="Camera the strokes are drawn through (empty: the panel's, "
                                                      "else the scene camera)")
    strokes: StringProperty(
        name="Strokes", options={'SKIP_SAVE'},
        description="JSON list of strokes, each a list of [x, y] points in the camera frame: x from 0 at its left "
                    "edge to 1 at its right, y from 0 at its bottom to 1 at its top (empty: the strokes drawn in the "
                    "scene)",
    )
    reach: FloatProperty(
        name="Reach", default=0.0, min=0.0, soft_max=2000.0, unit='LENGTH', options={'SKIP_SAVE'},
        description="Distance from the sketched silhouettes beyond which the terrain stays as it was (0: eight times "
                    "the largest height change, at most half the distance from the camera to the nearest silhouette; "
                    "unset: the panel's)",
    )
    max_change: FloatProperty(
        name="Largest Change", default=0.0, min=0.0, unit='LENGTH', options={'SKIP_SAVE'},
        description="Largest height change the sketch may make; a sketch asking for more is refused with the figure "
                    "(0: the terrain's relief, at least a quarter of its shorter side)",
    )
    completion: BoolProperty(
        name="Complete to Ground", default=True, options={'SKIP_SAVE'},
        description="Extend each silhouette along its ends until it meets the terrain (unset: the panel's)",
    )

    def _prepare(self, context):
        scene = context.scene
        settings = scene.worldpaint.sketch
        obj = editable_terrain(context, self.terrain)
        camera_obj = sketch_strokes.sketch_camera(context, settings, self.camera)
        camera = sketch.engine_camera(scene, camera_obj)
        self._from_scene = not self.strokes
        self._origins = None
        if self._from_scene:
            # the panel's source: the strokes drawn with Sketch Silhouettes, or an annotation layer's
            found = sketch_strokes.sketch_strokes(context, settings, camera_obj)
            for reason in found.skipped:
                self.report({'WARNING'}, reason)
            strokes = list(found)
            if settings.source == 'STROKES':
                self._origins = found.origins
        else:
            strokes = strokes_from_json(self.strokes)
        short = [k for k, s in enumerate(strokes) if len(s) < 2]
        if short:
            raise WorldPaintError(f"Stroke(s) {', '.join(map(str, short))} have fewer than two points")
        if not strokes:
            raise WorldPaintError("Nothing to apply: draw silhouettes with the Sketch Silhouettes tool first")
        self._standing = terrain_edit.Standing(scene)
        with terrain_edit.without_key(obj, sketch.SKETCH_KEY):
            heightfield = terrain.engine_terrain(context, obj)
        self._vertices = terrain_edit.basis_world(obj)
        reseated = self._standing.points() if settings.reseat else self._vertices[:0, :2]
        self._terrain_obj = obj
        self._reseat = settings.reseat
        self._show = settings.show_features
        self._bevel = 0.002 * float(np.ptp(self._vertices[:, :2], axis=0).max(initial=1.0))
        self._arguments = (heightfield, camera, strokes, np.vstack([self._vertices[:, :2], reseated]))
        reach = setting(self, "reach", settings.reach)
        self._call = dict(reach=reach if reach > 0.0 else None, completion=setting(self, "completion",
                                                                                   settings.completion),
                          aspect=sketch.frame_aspect(scene),
                          max_change=self.max_change if self.max_change > 0.0 else None)

    def _compute(self, progress):
        return engine.apply_sketch(*self._arguments, progress=progress, **self._call)

    def _apply(self, context, result):
        n = len(self._vertices)
        dz = result.displacement
        changed = dz[:n]
        if np.abs(changed).max(initial=0.0) <= UNMOVED and not terrain_edit.has_shape_key(self._terrain_obj,
                                                                                       sketch.SKETCH_KEY):
            self.report({'WARNING'}, "The sketch needs no change to the terrain: it already shows these silhouettes")
            return {'CANCELLED'}
        terrain_edit.write_shape_key(self._terrain_obj, sketch.SKETCH_KEY, changed)
        if self._reseat:
            self._standing.reseat(dz[n:], "sketch")
        if self._origins is not None:
            drawn = context.scene.worldpaint.sketch.strokes
            for stroke in drawn:
                stroke.depth_rank = -1
            for rank, k in enumerate(result.order):
                if 0 <= k < len(self._origins) and self._origins[k] < len(drawn):
                    drawn[self._origins[k]].depth_rank = rank
        if self._show:
            sketch.show(context.scene, result, self._bevel)
        else:
            sketch.clear_display(context.scene)
        embedded = sum(1 for s in result.sources if s == sketch.EMBEDDED)
        skyline = sum(1 for s in result.sources if s == sketch.SKYLINE)
        s = result.seconds
        self.report({'INFO'}, f"Sketch applied to '{self._terrain_obj.name}': {len(result.order)} stroke(s), "
                              f"{result.junctions} T-junction(s), {len(result.curves) - embedded - skyline} on "
                              f"terrain features, {skyline} on the skyline, {embedded} embedded; "
                              f"{len(result.lowered)} silhouette(s) lowered in "
                              f"{result.rounds} round(s); raised {max(changed.max(), 0.0):.1f} m, lowered "
                              f"{max(-changed.min(), 0.0) + 0.0:.1f} m (shape key '{sketch.SKETCH_KEY}'); "
                              f"{sum(s.values()):.2f} s")
        if result.hidden_columns:
            self.report({'WARNING'}, f"Part of the sketch is still hidden ({result.hidden_columns} image columns): "
                                     "draw it higher, or over terrain farther away")
        return {'FINISHED'}
