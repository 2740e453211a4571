"""The variety test tree: a low-poly birch written as a Wavefront OBJ (``assets/birch.obj`` with ``birch.mtl``).

Six components, one material each (Blender imports them as six material slots, and Decompose Model by Materials cuts
the tree along them), joined by five rings of shared vertices:

    0 trunk     an 8-sided trunk of 9 segments with a base cap and two branch holes of two quads each
    1 branch_a  a 6-sided branch out of the lower hole, rising outwards (5 segments)
    2 branch_b  the same out of the upper hole, on the other side
    3 crown     a lathed leaf mass closing the trunk's top ring, with 10 leaf clumps around it
    4 clump_a   a lathed leaf mass closing branch a's tip ring, with 7 leaf clumps
    5 clump_b   the same on branch b

Every leaf clump is a closed icosahedron set into its leaf mass (their faces cross: the intersections a real low-poly
tree has, which the variety check labels and allows), so the whole tree is closed (watertight), and deleting a
clump's 20 faces leaves it closed. Bark faces take the left half of the texture (u in [0, 0.5]), leaves the right.
Z is up, metres: import with Forward Y, Up Z.

Pure Python and numpy, seeded: ``python assets/birch.py`` writes the same two files every time.
"""

import math
import pathlib

import numpy as np

COMPONENTS = ("trunk", "branch_a", "branch_b", "crown", "clump_a", "clump_b")
COLORS = {"trunk": (0.90, 0.89, 0.84), "branch_a": (0.82, 0.80, 0.74), "branch_b": (0.82, 0.80, 0.74),
          "crown": (0.36, 0.58, 0.18), "clump_a": (0.42, 0.63, 0.20), "clump_b": (0.30, 0.52, 0.16)}
SIDES, SEGMENTS = 8, 9
HOLES = ((3, 0, 1), (5, 4, 2))  # (trunk segment, first side, branch component): two quads wide, one tall


class Mesh:
    def __init__(self):
        self.v, self.faces = [], []  # faces: (component, vertex indices)

    def vertex(self, p):
        self.v.append(np.asarray(p, dtype=float))
        return len(self.v) - 1

    def face(self, component, corners):
        self.faces.append((component, list(corners)))


def icosahedron(mesh, component, centre, radius):
    """A closed 20-face clump."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    raw = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
           (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    ids = [mesh.vertex(np.asarray(centre) + radius * np.asarray(p) / math.hypot(*p)) for p in raw]
    tris = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
            (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
            (8, 6, 7), (9, 8, 1)]
    for a, b, c in tris:
        mesh.face(component, (ids[a], ids[b], ids[c]))


def frame(axis):
    """Two unit vectors perpendicular to ``axis`` and to each other."""
    a = axis / np.linalg.norm(axis)
    u = np.cross(a, (0.0, 0.0, 1.0) if abs(a[2]) < 0.9 else (1.0, 0.0, 0.0))
    u /= np.linalg.norm(u)
    return a, u, np.cross(a, u)


def leaf_mass(mesh, component, ring, axis, profile, clumps, rng):
    """Closes the open ``ring`` (vertex ids, in order) with a lathed mass along ``axis``: ``profile`` is (height,
    radius) per layer, then the apex height; ``clumps`` icosahedra are set into its upper part."""
    a, u, w = frame(np.asarray(axis, dtype=float))
    pts = np.array([mesh.v[i] for i in ring])
    centre = pts.mean(axis=0)
    out = [(p - centre) - np.dot(p - centre, a) * a for p in pts]
    out = [d / np.linalg.norm(d) for d in out]
    prev = list(ring)
    n = len(ring)
    for h, r in profile[:-1]:
        layer = [mesh.vertex(centre + a * h + d * r) for d in out]
        for k in range(n):
            j = (k + 1) % n
            mesh.face(component, (prev[k], prev[j], layer[j], layer[k]))
        prev = layer
    apex = mesh.vertex(centre + a * profile[-1][0])
    for k in range(n):
        mesh.face(component, (prev[k], prev[(k + 1) % n], apex))
    widest = max(r for _, r in profile[:-1])
    middle = 0.55 * profile[-1][0]
    for k in range(clumps):
        turn = 2.0 * math.pi * (k + rng.uniform(-0.2, 0.2)) / clumps
        rise = middle + rng.uniform(-0.15, 0.35) * profile[-1][0]
        spot = centre + a * rise + (u * math.cos(turn) + w * math.sin(turn)) * 0.85 * widest
        icosahedron(mesh, component, spot, rng.uniform(0.32, 0.42) * widest)


def birch(seed=7):
    mesh = Mesh()
    rng = np.random.default_rng(seed)
    ring = [[0] * SIDES for _ in range(SEGMENTS + 1)]
    for r in range(SEGMENTS + 1):
        radius = 0.24 - 0.011 * r
        sway = np.array([0.05 * math.sin(0.7 * r), 0.04 * math.sin(0.5 * r + 1.0), float(r)])
        for s in range(SIDES):
            a = 2.0 * math.pi * s / SIDES
            ring[r][s] = mesh.vertex(sway + radius * np.array([math.cos(a), math.sin(a), 0.0]))
    holes = {(seg, s + k) for seg, s, _ in HOLES for k in (0, 1)}
    for seg in range(SEGMENTS):
        for s in range(SIDES):
            if (seg, s) not in holes:
                j = (s + 1) % SIDES
                mesh.face(0, (ring[seg][s], ring[seg][j], ring[seg + 1][j], ring[seg + 1][s]))
    mesh.face(0, [ring[0][s] for s in reversed(range(SIDES))])
    tips = {}
    for seg, s, component in HOLES:
        hole = [ring[seg][s], ring[seg][s + 1], ring[seg][s + 2], ring[seg + 1][s + 2], ring[seg + 1][s + 1],
                ring[seg + 1][s]]
        base = np.array([mesh.v[i] for i in hole])
        centre = base.mean(axis=0)
        out = np.array([centre[0], centre[1], 0.0])
        direction = out / np.linalg.norm(out) + np.array([0.0, 0.0, 0.9])
        direction /= np.linalg.norm(direction)
        prev = hole
        for k in range(1, 6):
            shrink = 1.0 - 0.13 * k
            layer = [mesh.vertex(centre + direction * 2.3 * k / 5 + (p - centre) * shrink) for p in base]
            for e in range(6):
                f = (e + 1) % 6
                mesh.face(component, (prev[e], prev[f], layer[f], layer[e]))
            prev = layer
        tips[component] = (prev, direction)
    profile = [(0.25, 0.35), (0.55, 0.62), (0.95, 0.70), (1.35, 0.58), (1.65, 0.34), (1.85, 0.0)]
    for component, clump in ((1, 4), (2, 5)):
        tip, direction = tips[component]
        leaf_mass(mesh, clump, tip, direction, profile, 7, rng)
    crown = [(0.3, 0.55), (0.8, 1.05), (1.45, 1.25), (2.1, 1.15), (2.7, 0.85), (3.1, 0.45), (3.35, 0.0)]
    leaf_mass(mesh, 3, ring[SEGMENTS], (0.0, 0.0, 1.0), crown, 10, rng)
    return mesh


def face_uvs(component, corners, centre):
    """Bark: around the trunk or branch and up it, in the left half of the texture; leaves: around their mass, in the
    right half. The corners of a face take their angles next to the face's own (no face spans the wrap's seam)."""
    d = corners - centre
    mid = d.mean(axis=0)
    base = math.atan2(mid[1], mid[0])
    turn = [base + (math.atan2(p[1], p[0]) - base + math.pi) % (2.0 * math.pi) - math.pi for p in d]
    u = [0.5 * ((base / (2.0 * math.pi)) % 1.0) + 0.5 * (t - base) / (2.0 * math.pi) for t in turn]
    if component < 3:
        return [(x, min(max(p[2] / 14.0, 0.0), 1.0)) for x, p in zip(u, corners, strict=True)]
    return [(0.5 + x, 0.5 + 0.5 * q[2] / (np.linalg.norm(q) + 1e-9)) for x, q in zip(u, d, strict=True)]


def write(mesh, obj_path, mtl_path):
    v = np.array(mesh.v)
    centres = {}
    for c, corners in mesh.faces:
        centres.setdefault(c, []).extend(corners)
    centres = {c: v[sorted(set(ids))].mean(axis=0) for c, ids in centres.items()}
    lines = [f"# A low-poly birch for worldpaint's model variety: {len(mesh.faces)} faces, 6 components (one material",
             "# each) joined by rings of shared vertices; closed. Z up, metres. Made by assets/birch.py.",
             f"mtllib {mtl_path.name}", "o Birch"]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in v]
    texcoords, body = [], []
    for c, name in enumerate(COMPONENTS):
        body.append(f"usemtl {name}")
        for component, corners in mesh.faces:
            if component != c:
                continue
            coords = face_uvs(c, v[corners], centres[c])
            refs = []
            for t in coords:
                texcoords.append(t)
                refs.append(f"{corners[len(refs)] + 1}/{len(texcoords)}")
            body.append("f " + " ".join(refs))
    lines += [f"vt {a:.6f} {b:.6f}" for a, b in texcoords]
    lines += body
    obj_path.write_text("\n".join(lines) + "\n")
    mtl = ["# Materials of birch.obj: one per component."]
    for name in COMPONENTS:
        r, g, b = COLORS[name]
        mtl += [f"newmtl {name}", f"Kd {r:.3f} {g:.3f} {b:.3f}", "Ka 0 0 0", "Ks 0 0 0", "d 1", "illum 1", ""]
    mtl_path.write_text("\n".join(mtl))


if __name__ == "__main__":
    here = pathlib.Path(__file__).resolve().parent
    birch_mesh = birch()
    write(birch_mesh, here / "birch.obj", here / "birch.mtl")
    print(f"birch.obj: {len(birch_mesh.v)} vertices, {len(birch_mesh.faces)} faces")
