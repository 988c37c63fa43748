# Blender's Surface Deform modifier on the meshes cagewrap's bench uses, run inside Blender:
#   blender -b --factory-startup --python-exit-code 1 --python surface_deform.py -- \
#     --skin skin.obj --cage cage.obj --posed-cage cage_posed.obj --changes 20 --deformed out.bin --json out.json
# The OBJ files are read here, vertex for vertex in file order (Blender's importers may split or merge
# vertices), so that both tools deform exactly the same points. Times the bind (the bind operator
# and the evaluation that performs it), then per cage change the depsgraph evaluation after the
# cage's vertices moved to the next of `changes` states between rest and posed (as `cagewrap bench`
# does); writes the skin deformed by the posed cage (raw float32 #P x 3, for `cagewrap bench
# --score-deformed`) and the figures (JSON).
import argparse
from array import array
import json
import resource
import statistics
import sys
import time

import bpy


def peak_rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def read_obj(path):
    """Vertices (flat float32 #V x 3) and polygons (corner counts, 0-based corner indices) of an OBJ."""
    verts, counts, corners = [], [], []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            if line.startswith("v "):
                verts.append(line[2:])
            elif line.startswith("f "):
                tokens = line.split()[1:]
                counts.append(len(tokens))
                for t in tokens:
                    i = int(t.split("/")[0])
                    if i == 0 or abs(i) > len(verts):
                        sys.exit(f"{path}:{number}: face corner {i} names no vertex ({len(verts)} so far)")
                    corners.append(i - 1 if i > 0 else len(verts) + i)
    v = array("f", map(float, " ".join(verts).split()))  # parsed in double, rounded to float once
    if len(v) != 3 * len(verts):
        sys.exit(f"{path}: a vertex line has not three coordinates")
    return v, array("i", counts), array("i", corners)


def make_object(name, verts, counts, corners):
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(verts) // 3)
    me.vertices.foreach_set("co", verts)
    me.loops.add(len(corners))
    me.loops.foreach_set("vertex_index", corners)
    me.polygons.add(len(counts))
    starts, total = array("i", bytes(4 * len(counts))), 0
    for i, c in enumerate(counts):
        starts[i], total = total, total + c
    me.polygons.foreach_set("loop_start", starts)
    me.polygons.foreach_set("loop_total", counts)
    me.update(calc_edges=True)
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="surface_deform.py")
    ap.add_argument("--skin", required=True)
    ap.add_argument("--cage", required=True)
    ap.add_argument("--posed-cage", required=True)
    ap.add_argument("--changes", type=int, default=20)
    ap.add_argument("--falloff", type=float, default=4.0)
    ap.add_argument("--deformed", required=True)
    ap.add_argument("--json", required=True)
    a = ap.parse_args(argv)
    if a.changes < 1:
        sys.exit("--changes must be at least 1")
    baseline = peak_rss_mb()
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    skin = make_object("skin", *read_obj(a.skin))
    rest, cage_counts, cage_corners = read_obj(a.cage)
    posed = read_obj(a.posed_cage)[0]
    if len(posed) != len(rest):
        sys.exit(f"{a.posed_cage} has {len(posed) // 3} vertices but {a.cage} has {len(rest) // 3}")
    cage = make_object("cage", rest, cage_counts, cage_corners)
    n = len(skin.data.vertices)

    mod = skin.modifiers.new("SurfaceDeform", "SURFACE_DEFORM")
    mod.target = cage
    mod.falloff = a.falloff
    bpy.context.view_layer.objects.active = skin
    depsgraph = bpy.context.evaluated_depsgraph_get()
    depsgraph.update()  # the unbound state evaluated first: not part of the bind

    t0 = time.perf_counter()
    with bpy.context.temp_override(object=skin, active_object=skin):
        bpy.ops.object.surfacedeform_bind(modifier=mod.name)
    depsgraph.update()
    bind_s = time.perf_counter() - t0
    if not mod.is_bound:
        sys.exit("Surface Deform did not bind (see Blender's messages above: concave or invalid target polygons?)")

    # the same cage states as cagewrap bench: mix(rest, posed, k / changes) in double, k = 1..changes
    # (glm::mix: r * (1 - t) + p * t)
    states = [array("f", (r * (1 - k / a.changes) + p * (k / a.changes) for r, p in zip(rest, posed)))
              for k in range(1, a.changes + 1)]
    ms = []
    for state in states:
        cage.data.vertices.foreach_set("co", state)
        cage.data.update()
        t0 = time.perf_counter()
        depsgraph.update()
        ms.append((time.perf_counter() - t0) * 1e3)
    out = array("f", bytes(12 * n))
    evaluated = skin.evaluated_get(depsgraph)
    if len(evaluated.data.vertices) != n:
        sys.exit(f"the evaluated skin has {len(evaluated.data.vertices)} vertices, not {n}")
    evaluated.data.vertices.foreach_get("co", out)
    if sys.byteorder != "little":
        out.byteswap()
    with open(a.deformed, "wb") as f:
        out.tofile(f)
    figures = {
        "tool": "Blender " + bpy.app.version_string + " Surface Deform (falloff %g)" % a.falloff,
        "points": n,
        "cage_polygons": len(cage_counts),
        "bind_s": bind_s,
        "deform_median_ms": statistics.median(ms),
        "deform_min_ms": min(ms),
        "changes": a.changes,
        "peak_rss_mb": peak_rss_mb(),
        "baseline_rss_mb": baseline,
    }
    with open(a.json, "w") as f:
        json.dump(figures, f, indent=1)
    print("surface deform: " + json.dumps(figures))


main()
