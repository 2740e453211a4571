"""Learn Color: the statistics of the selected example objects and curves become a new color in the palette.

Selected point clouds and synthesized curves (a painted forest, an imported place) are examples too: what they hold
inside the region is learned as if placed by hand."""

import bpy
from bpy.props import BoolProperty, EnumProperty, StringProperty

from ..bridge import WorldPaintError, curves, engine, instances, regions, scene_maps, terrain
from ..props import LEARN_RELATIONS
from .background import with_progress
from .colors import add_palette_color, fidelity_view, unique_name
from .common import RegionProperties, TerrainProperty, reports_errors


def split_pair(item, what):
    """(category, other) of a pair written 'category:other'; the other may be a scene map ('group:Moisture')."""
    category, colon, other = item.partition(":")
    category, other = category.strip(), other.strip()
    if not (colon and category and other):
        raise WorldPaintError(f"{what} pair '{item}' is not of the form 'category:other'")
    return category, other


class WORLDPAINT_OT_set_learn_relation(bpy.types.Operator):
    """Set how Learn Color relates a category to another category or a map (click: the next choice)"""

    bl_idname = "worldpaint.set_learn_relation"
    bl_label = "Set Learn Relation"
    bl_options = {'REGISTER', 'UNDO'}

    category: StringProperty(name="Category")
    other: StringProperty(name="Other", description="Another category, or a map")
    how: EnumProperty(name="How", items=(*LEARN_RELATIONS, ("NEXT", "Next", "The next of Auto, None, Oriented")),
                      default="NEXT")

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint
        if not (self.category and self.other):
            raise WorldPaintError("Give the category and the other category or map of the relation")
        kinds = {c.name: c.kind for c in settings.categories}
        can_orient = kinds.get(self.category) == "distribution" and kinds.get(self.other) == "distribution"
        how = self.how
        if how == "NEXT":
            order = ["AUTO", "NONE", "ORIENTED"] if can_orient else ["AUTO", "NONE"]
            current = settings.learn_relation(self.category, self.other)
            how = order[(order.index(current) + 1) % len(order)] if current in order else "AUTO"
        elif how == "ORIENTED" and not can_orient:
            raise WorldPaintError(f"Only two distributions can have an oriented relation, not {self.category} and "
                                  f"{self.other}")
        cells = settings.learn_relations
        for index in reversed(range(len(cells))):
            if (cells[index].category, cells[index].other) == (self.category, self.other):
                cells.remove(index)
        if how != "AUTO":
            cell = cells.add()
            cell.category, cell.other, cell.how = self.category, self.other, how
        return {'FINISHED'}


class WORLDPAINT_OT_toggle_learn_map(bpy.types.Operator):
    """Learn Color learns this map made in the scene too, or no longer"""

    bl_idname = "worldpaint.toggle_learn_map"
    bl_label = "Toggle Scene Map"
    bl_options = {'REGISTER', 'UNDO'}

    name: StringProperty(name="Map", description="group:<vertex group>, attribute:<name>, image:<name> or "
                         "distance:<collection>")

    @reports_errors
    def execute(self, context):
        settings = context.scene.worldpaint
        scene_maps.check_names([self.name])
        chosen = scene_maps.names_in(settings.learn_maps)
        chosen = [name for name in chosen if name != self.name] if self.name in chosen else chosen + [self.name]
        settings.learn_maps = ",".join(chosen)
        return {'FINISHED'}


class WORLDPAINT_OT_learn_color(RegionProperties, TerrainProperty, bpy.types.Operator):
    """Learn the arrangement of the selected example objects as a new palette color"""

    bl_idname = "worldpaint.learn_color"
    bl_label = "Learn Color"
    bl_options = {'REGISTER', 'UNDO'}

    name: StringProperty(name="Name", description="Name of the new color (empty: Color N)")
    use_elevation: BoolProperty(
        name="Height Preference",
        default=False,
        description="Also learn which terrain heights the example occupies (the slope preference is always learned); "
        "heights beyond the example's range are treated like its highest or lowest ones",
    )

    maps: StringProperty(
        name="Scene Maps",
        description="Maps made in the scene to learn too, comma-separated: group:<vertex group>, "
        "attribute:<attribute>, image:<image texture>, distance:<collection> (Paste reads the same maps on the "
        "destination's terrain)",
    )
    oriented: StringProperty(
        name="Oriented Pairs",
        description="Pairs 'category:other', comma-separated, whose relation also depends on direction (an oriented "
        "rdf: houses facing a road, grass downhill of rocks)",
    )
    independent: StringProperty(
        name="Independent Pairs",
        description="Pairs 'category:other' (another category or a map), comma-separated, learned as independent: "
        "the category is painted as if the other were not there",
    )

    def matrix_cell(self, settings, pair, how, present):
        """Whether ``pair`` is a cell of the Learn Matrix set to ``how`` that names a category or map the example
        does not have (a cell left from another example): such a cell is left out, and said so."""
        absent = [name for name in pair if name not in present]
        if not absent or settings.learn_relation(*pair) != how:
            return False
        label = {"NONE": "None", "ORIENTED": "Oriented"}[how]
        self._left_out.append(f"the Learn Matrix cell {pair[0]}: {pair[1]} ({label}) names "
                              f"{', '.join(absent)}, which this example does not have")
        return True

    def oriented_pairs(self, categories, settings, present):
        """The oriented pairs as (category, other), checked against the categories; the Learn Matrix's cells for
        categories the example does not have are left out."""
        kinds = {c["name"]: c["kind"] for c in categories}
        pairs = []
        for item in scene_maps.names_in(self.oriented):
            pair = split_pair(item, "Oriented")
            if self.matrix_cell(settings, pair, "ORIENTED", present):
                continue
            unknown = [name for name in pair if name not in kinds]
            if unknown:
                raise WorldPaintError(f"Oriented pair '{item}': no category {', '.join(unknown)} in the example")
            structured = [name for name in pair if kinds[name] in ("graph", "polygon")]
            if structured:
                raise WorldPaintError(f"Oriented pair '{item}': {', '.join(structured)} is a graph or polygon, "
                                      "seen through its distance; oriented pairs are between distributions")
            pairs.append(pair)
        return pairs

    def independent_pairs(self, color_json, settings, present):
        """The interactions of the learned color that the independent pairs switch off, as (category, other); the
        Learn Matrix's cells for categories the example does not have are left out."""
        learned = {(i.category, i.other) for i in engine.color_summary(color_json).interactions}
        off = set()
        for item in scene_maps.names_in(self.independent):
            category, other = split_pair(item, "Independent")
            if self.matrix_cell(settings, (category, other), "NONE", present):
                continue
            # a pair between two categories is one interaction, whichever of them the priority order puts first
            found = [pair for pair in ((category, other), (other, category)) if pair in learned]
            if not found:
                cell = (f"The Learn Matrix cell {category}: {other} (None)" if settings.learn_relation(
                    category, other) == "NONE" else f"Independent pair '{item}'")
                raise WorldPaintError(f"{cell}: the example gives no interaction between {category} and {other}")
            off.add(found[0])
        return off

    @reports_errors
    def execute(self, context):
        scene = context.scene
        settings = scene.worldpaint
        terrain_obj = terrain.terrain_object(context, self.terrain)
        mode = self.resolved_region_mode(context)
        region_curve = regions.find_curve(context, self.curve) if mode == 'CURVE' else None
        examples = instances.example_objects(context.selected_objects, exclude=[terrain_obj])
        drawn = curves.example_curves(context.selected_objects, exclude=[terrain_obj, region_curve])
        # point clouds and synthesized curves selected (an imported place, a painted forest): what they hold
        clouds = [o for o in context.selected_objects if o.get(instances.POINTS_TAG) and o.type == 'MESH']
        painted = [(o, o[instances.STRUCTURE_TAG], all(s.use_cyclic_u for s in o.data.splines))
                   for o in context.selected_objects
                   if o.type == 'CURVE' and o.get(instances.STRUCTURE_TAG) and o.data.splines and o != region_curve]
        if not (examples or drawn or clouds or painted):
            raise WorldPaintError(
                "Nothing to learn: select the example objects (collection instances, linked duplicates or "
                "objects with a 'wp_category' property), curves (roads, rivers; closed: islands, lakes), or the "
                "point clouds and curves of a painted or imported place"
            )
        # merged silently, two things of one name would be learned as one and pasted as either
        instances.check_example_categories(examples, drawn)
        # the region is around the example objects; curves and clouds (which usually reach beyond it) only when alone
        region = regions.region_for(
            context,
            mode,
            objects=[obj for obj, _ in examples] or [obj for obj, _, _ in drawn + painted] + clouds,
            use_bounds=not examples,
            **self.region_kwargs(),
        )
        maps = ["slope", "elevation"] if self.use_elevation else ["slope"]
        maps = list(dict.fromkeys(maps + scene_maps.check_names(scene_maps.names_in(self.maps))))
        heightfield = terrain.engine_terrain(context, terrain_obj, maps)
        terrain.check_region_on_terrain(heightfield, region, "example")

        new = instances.new_categories(settings, examples + [(o, o[instances.POINTS_TAG]) for o in clouds],
                                       drawn + painted)
        categories = instances.merged_categories(settings, new)
        exemplar = instances.example_set(examples, categories)
        for cloud in clouds:
            co, rotation, scale, prototype = instances.point_cloud_arrays(cloud)
            exemplar.append(cloud[instances.POINTS_TAG], co[:, :2], rotation, scale, prototype, locked=True,
                            heights=co[:, 2])
        structures = curves.StructureSet(categories=categories)
        for obj, category, _ in drawn + painted:
            structures.add(obj, category, locked=True)
        # a typed name the palette has is numbered, as the Pipette and Interpolate Colors do
        name = unique_name(settings.palette, self.name or "Color")
        scene_data = engine.scene(heightfield, exemplar.engine_arrays(), structures.engine_arrays())
        # what the example has: a cell of the Learn Matrix naming anything else is left from another example
        present = ({c for _, c in examples} | {c for _, c, _ in drawn + painted}
                   | {o[instances.POINTS_TAG] for o in clouds} | set(maps))
        self._left_out = []
        oriented = self.oriented_pairs(categories, settings, present)
        color_json = engine.learn_color(scene_data, region, name, maps, oriented)
        off = self.independent_pairs(color_json, settings, present)
        painted_json = engine.color_without_interactions(color_json, off) if off else color_json
        # the color painted into its own example region and learned back: how well it reproduces the example
        fidelity = with_progress(context, lambda progress: fidelity_view(painted_json, heightfield, progress))

        # validated and computed: now change the scene
        instances.add_categories(settings, new)
        entry = add_palette_color(settings, name, color_json, fidelity, off=off)
        n_categories = len(present - set(maps))
        self.report({'INFO'}, f"Learned '{name}' from {len(exemplar)} instances and {len(structures)} curves in "
                              f"{n_categories} categories; painted into its example's region: {entry.fidelity_line()}")
        if self._left_out:
            self.report({'INFO'}, f"Not used: {'; '.join(self._left_out)}")
        flat = scene_maps.constant_in(heightfield, maps, region, terrain_obj)
        if flat:
            self.report({'WARNING'}, f"Nothing learned from a map: {'; '.join(flat)}, so the example shows nothing "
                                     "of how its categories follow it (where it differs, the color paints at most "
                                     "its mean density)")
        return {'FINISHED'}
