//! The terrain adapted to the water (thesis 4.4.2 "Constraint-based Terrain Deformation"): height differences
//! `d(x, y) = z − H(x, y)` from three kinds of constraints are diffused by the solver of [`crate::terrain_edit`]
//! into a displacement map `D`, and `H' = H + D`; beyond the falloff radius from every constraint the terrain
//! stays as it was.
//!
//! * **Border constraints** — on the contour `Ω` of the integration mesh: the bank comes to the water's level plus
//!   [`WaterfallDeformOptions::freeboard`] (of the higher water where two banks meet, as beside a stream above the pool
//!   it falls into). The contour is rasterized as the band of grid nodes outside the water and within
//!   [`WaterfallDeformOptions::bank_width`] of it (the footprint of [`super::integration`]), so that the bank holds on
//!   the grid whatever its direction. The nodes within a cell diagonal of the water come to the level of the water
//!   nearest to them, as the thesis's `Ω` does, and the freeboard starts beyond them: the terrain interpolated between
//!   them and the riverbed then stays under the water surface on any grid, also under a stream narrower than a cell.
//! * **Riverbed constraints** — every node inside the border, at distance `e` from the nearest border point, is
//!   fixed at `surface − ζ g(e / e_max)`: the profile `f_d` of the thesis, deepest (`ζ`, the section's depth) in
//!   the middle. The thesis wants the profile "a function of the river type" and does not give it; here streams
//!   and rivers get a flat-bottomed U, `g(x) = 1 − (1 − x)²`, the steep contact types (rapid, cascade,
//!   horsetail, block) the triangle of the section model, `g(x) = x`, and pools the U as a bowl.
//! * **Overhang constraints** — "along the border at the top of a free-fall, we set a displacement constraint
//!   `λu`, where `u` is the free-fall direction [...] In addition [...] `−λu` along the border of the receiving
//!   pool, under the free-fall." The pool border under the fall is read as the part of its contour facing back
//!   against `u` (outward normal within 60° of `−u`). The horizontal map is diffused with the same solver and
//!   applied after the vertical one, `H''(p) = H'(p − D_h(p))`.
//!
//! Free-fall footprints get no height constraint: the cliff under the sheet is left to the diffusion.

use super::classify::WaterfallType;
use super::integration::{WaterMesh, WaterPart, WaterfallFootprint};
use super::model::{ControllerKind, WaterfallNetwork};
use crate::error::{check, Result};
use crate::terrain::Heightfield;
use crate::terrain_edit::{
    diffuse, diffuse_horizontal, Constraints, Diffusion, DiffusionOptions, HorizontalConstraints,
    HorizontalDisplacement,
};
use glam::DVec2;

/// How the terrain is deformed.
#[derive(Clone, Debug)]
pub struct WaterfallDeformOptions {
    /// Height of the banks above the water (m).
    pub freeboard: f64,
    /// Width of the band of border constraints along the water (m); `None`: three grid cells.
    pub bank_width: Option<f64>,
    /// `λ`, the overhang displacement (m); 0: none.
    pub overhang: f64,
    /// Beyond this distance (m) from every constraint the terrain is unchanged.
    pub falloff: f64,
    /// Tolerance and cycle limit of the solver (its falloff is [`WaterfallDeformOptions::falloff`]).
    pub diffusion: DiffusionOptions,
}

impl Default for WaterfallDeformOptions {
    fn default() -> Self {
        WaterfallDeformOptions {
            freeboard: 0.3,
            bank_width: None,
            overhang: 1.0,
            falloff: 30.0,
            diffusion: DiffusionOptions {
                tolerance: 1e-4,
                ..DiffusionOptions::default()
            },
        }
    }
}

impl WaterfallDeformOptions {
    /// Checks that the heights and distances are finite and not negative (the bank width positive).
    pub fn validate(&self) -> Result<()> {
        check::non_negative("terrain deformation freeboard", self.freeboard)?;
        check::non_negative("terrain deformation overhang", self.overhang)?;
        check::non_negative("terrain deformation falloff", self.falloff)?;
        if let Some(b) = self.bank_width {
            check::positive("terrain deformation bank_width", b)?;
        }
        Ok(())
    }

    /// The bank band's width on a grid of `cell` metres.
    pub(crate) fn bank(&self, cell: f64) -> f64 {
        self.bank_width.unwrap_or(3.0 * cell)
    }
}

/// The deformed terrain and its maps.
#[derive(Clone, Debug)]
pub struct TerrainDeformation {
    /// `H'' `: the terrain after the vertical and the horizontal displacement.
    pub terrain: Heightfield,
    /// `D` and the solver's statistics.
    pub vertical: Diffusion,
    /// The horizontal displacement map (zero without overhangs).
    pub horizontal: HorizontalDisplacement,
    /// Nodes with a height constraint (border or riverbed), row-major.
    pub constrained: Vec<bool>,
    /// Nodes with an overhang constraint, row-major.
    pub overhang_constrained: Vec<bool>,
    /// Nodes with a riverbed constraint.
    pub riverbed_nodes: usize,
    /// Nodes with a border (bank) constraint.
    pub border_nodes: usize,
}

/// The riverbed profile `g` on `[0, 1]` (0 on the border, 1 in the middle).
pub(super) fn profile(part: WaterPart, kind: Option<WaterfallType>, x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    let u = 1.0 - (1.0 - x) * (1.0 - x);
    match (part, kind) {
        (WaterPart::Pool, _) => u,
        (_, Some(WaterfallType::Stream | WaterfallType::River)) => u,
        _ => x,
    }
}

/// Deforms the terrain under the network's water.
pub(crate) fn deform(
    terrain: &Heightfield,
    net: &WaterfallNetwork,
    mesh: &WaterMesh,
    footprint: &WaterfallFootprint,
    options: &WaterfallDeformOptions,
) -> Result<TerrainDeformation> {
    options.validate()?;
    check::fits_terrain(
        "water footprint",
        (footprint.nx, footprint.ny),
        (terrain.nx, terrain.ny),
    )?;
    let nx = terrain.nx;
    let bank = options.bank(terrain.cell);
    let mut c = Constraints::for_terrain(terrain);
    let (mut riverbed_nodes, mut border_nodes) = (0, 0);
    for (k, node) in footprint.nodes.iter().enumerate() {
        let Some(n) = node else {
            continue;
        };
        let h = terrain.heights[k] as f64;
        let target = if n.inside > 0.0 {
            let kind = match n.part {
                WaterPart::Contact => Some(net.segments[n.element].kind_of_water),
                WaterPart::FreeFall => continue,
                WaterPart::Pool => None,
            };
            riverbed_nodes += 1;
            n.surface - n.depth * profile(n.part, kind, n.inside / n.half_width.max(1e-9))
        } else if -n.inside <= bank && n.part != WaterPart::FreeFall {
            border_nodes += 1;
            if -n.inside < std::f64::consts::SQRT_2 * terrain.cell {
                n.surface
            } else {
                n.bank_level + options.freeboard
            }
        } else {
            continue;
        };
        c.set(k % nx, k / nx, target - h)?;
    }
    let diffusion = DiffusionOptions {
        falloff: Some(options.falloff),
        ..options.diffusion.clone()
    };
    let constrained = c.mask();
    let hc = overhangs(terrain, net, mesh, options.overhang)?;
    let overhang_constrained = hc.x.mask();
    let (vertical, horizontal) = rayon::join(
        || diffuse(&c, &diffusion),
        || diffuse_horizontal(&hc, &diffusion),
    );
    let (vertical, horizontal) = (vertical?, horizontal?);
    let lowered = vertical.apply(terrain)?;
    let mut out = horizontal.apply(&lowered)?;
    for (name, map) in &terrain.maps {
        out.maps.entry(name.clone()).or_insert_with(|| map.clone());
    }
    Ok(TerrainDeformation {
        terrain: out,
        vertical,
        horizontal,
        constrained,
        overhang_constrained,
        riverbed_nodes,
        border_nodes,
    })
}

/// The overhang constraints: `λu` on the lip of every free-fall, `−λu` on the back of its receiving pool.
fn overhangs(
    terrain: &Heightfield,
    net: &WaterfallNetwork,
    mesh: &WaterMesh,
    lambda: f64,
) -> Result<HorizontalConstraints> {
    let mut hc = HorizontalConstraints::for_terrain(terrain);
    if lambda == 0.0 {
        return Ok(hc);
    }
    let mut backs: Vec<(Vec<DVec2>, DVec2)> = Vec::new();
    for b in mesh
        .borders
        .iter()
        .filter(|b| b.part == WaterPart::FreeFall)
    {
        let Some(seg) = net.segments.get(b.element) else {
            continue;
        };
        let a = seg.arc;
        if net.graph.arcs[a].kind != ControllerKind::FreeFall {
            continue;
        }
        let u = super::integration::fall_direction(net, a);
        let lip: Vec<DVec2> = b.points.iter().map(|p| p.truncate()).collect();
        hc.polyline(terrain.origin, &lip, lambda * u)?;
        let to = net.graph.arcs[a].to;
        if let Some(pool) = mesh.pools.iter().find(|p| p.node == to) {
            let c = &pool.contour;
            let centre = c.iter().copied().sum::<DVec2>() / c.len() as f64;
            for k in 0..c.len() {
                let (p, q) = (c[k], c[(k + 1) % c.len()]);
                let m = 0.5 * (p + q) - centre;
                if m.dot(u) <= -0.5 * m.length() {
                    backs.push((vec![p, q], -lambda * u));
                }
            }
        }
    }
    // the lips first: where a lip and a back wall share a node, the lip keeps it
    for (edge, v) in backs {
        hc.polyline(terrain.origin, &edge, v)?;
    }
    Ok(hc)
}
