"""What Paste Color, Stretch Region, Gradient and Blur share: each synthesizes in a region of the scene's content,
with one engine function run in the background (see ``background``)."""

from ..bridge import engine, terrain
from .background import BackgroundOperator
from .common import RegionSynthesisProperties, SceneContent, report_missing


class RegionSynthesisOperator(BackgroundOperator, RegionSynthesisProperties):
    """Reads the scene's content and the region, runs the engine function named ``engine_function`` on them with the
    arguments of ``_arguments`` and the synthesis settings, then writes its edit and reports it with ``_report``."""

    bl_options = {'REGISTER', 'UNDO'}
    engine_function = ""
    # what the region is called in the error when it leaves the terrain (None: not checked)
    region_role = None

    def _colors(self, context):
        """The colors the operator paints (``engine.ColorSummary``, resolved first): their categories are read
        besides the scene's, and the scene maps they follow."""
        return ()

    def _painted_color(self):
        """The palette color whose own synthesis settings apply (resolved in ``_colors``); None: the panel's."""
        return None

    def _arguments(self, context, region):
        """The engine function's own arguments, validated."""
        return {}

    def _edit(self, result):
        """The ``engine.Edit`` in the engine function's result."""
        return result

    def _report(self, applied, result):
        raise NotImplementedError

    def _prepare(self, context):
        """Validates the inputs and extracts what the engine needs; changes nothing."""
        self._content = SceneContent(context, self.terrain, self._colors(context))
        region = self.destination(context, self._content.terrain_obj)
        if self.region_role is not None:
            terrain.check_region_on_terrain(self._content.heightfield, region, self.region_role)
        self._call = dict(region=region, **self._arguments(context, region),
                          **self.synthesis_arguments(context.scene.worldpaint, self._painted_color()))

    def _compute(self, progress):
        compute = getattr(engine, self.engine_function)
        return compute(self._content.engine_scene(), progress=progress, **self._call)

    def _apply(self, context, result):
        applied = self._content.apply(context, self._edit(result))
        self._report(applied, result)
        report_missing(self, applied)
        return {'FINISHED'}
