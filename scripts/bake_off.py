#!/usr/bin/env python3
"""The bake-off of docs/results.md: every technique against the supersampled truth.

Runs `leanfade eval` for each configuration below (argument lists, no shell), keeps each run's
results.json under OUT/<name>/, and writes OUT/bake_off.csv, OUT/bake_off.json and the Markdown
table of docs/results.md (OUT/bake_off.md): per configuration, technique and shininess, the
energy over every covered pixel and over the eroded mask (seed-summed where --seeds > 1), the
relative RMSE and the flicker against the truth's, at each distance.

The peer rows "roughness (Filament)" run Filament's `roughness-prefilter` (Debian
libfilament-tools) on the same normal map (on the corpus: every configuration of a normal map;
`--no-peers` skips them, `--peers-only` runs nothing else), once per shininess with the base roughness
r0 = (2/s)^(1/4) of that shininess, `--linear`, and evaluate its MIP files as the roughness
technique's input (`leanfade eval --roughness-mips NAME_0.png`). roughness-prefilter reads PNG, not
JPEG or DDS: such a map is converted first with ImageMagick's `convert` (Debian imagemagick). The
built-in sets' real normal maps are those of Debian's assimp-testmodels.

The real-map corpus (`--corpus`, CORPUS below: maps of Debian's redeclipse-data,
supertuxkart-data, cube2-data, freeorion-data and glmark2-data at their native size) runs each
map on the plane near its mirror direction and on the teapot lit from the front and from behind,
at 1.5-64 radii (the plane to 32), with each BRDF of --brdfs.

Usage: scripts/bake_off.py [--leanfade build/tools/leanfade/leanfade] [--out out/bake_off]
                           [--seeds 8] [--frames 4] [--only NAME,...]
                           [--corpus [--brdfs bp,ct]] [--techniques LIST]
                           [--texture-sizes 256,1024,4096] [--frame-size 192]
                           [--geometric-aa on|off] [--no-peers | --peers-only]

--texture-sizes runs the built-in sets (bumps, noise, ridges) at each size (texels per side);
a size other than 256 adds `_tSIZE` to the configuration's name. The real maps run at their own.
--frame-size renders every configuration at N x N pixels (`eval --size`) instead of 256 x 256
and adds `_fN` to its name.
--geometric-aa (corpus runs) draws every technique with geometric AA on or off (`_aaon`,
`_aaoff`); without it each technique has eval's default (`auto`: on for two-lobe only).
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys

TECHNIQUES = "bump,toksvig,clean,roughness,lean,fade,two-lobe"
PLANE_GLINT = ["--scene", "plane", "--view-dir", "0,1,1", "--light-dir", "0,1,-1", "--tiling", "0.1"]
RIBS = "/usr/share/assimp/models/glTF2/ClearCoat-glTF/RibsNormal.png"

# The real-map corpus (docs/results.md §9): normal and height maps that Debian data packages ship,
# at their native size. (tag, package, path, eval flags of the map). `--directx` where the map's
# green points down (measured: the curl of its slope field, docs/results.md §9); height maps with
# the strength (height per texel) that gives their features slopes of about 0.1-0.5.
RD = "/usr/share/games/redeclipse/data/"
STK = "/usr/share/games/supertuxkart/data/"
C2 = "/usr/share/games/cube2/packages/"
CORPUS = [
    ("grate01", "redeclipse-data", RD + "jojo/grate01/normal.png", ["--directx"]),
    ("grate02", "redeclipse-data", RD + "jojo/grate02/normal.png", ["--directx"]),
    ("ground010", "supertuxkart-data", STK + "tracks/cave/Ground010_1K_Normal.png", ["--directx"]),
    ("crate1", "redeclipse-data", RD + "trak/trak6/crate1_nm.png", ["--directx"]),
    ("tile2", "redeclipse-data", RD + "trak/trak6/tile2_nm.png", ["--directx"]),
    ("brick01", "redeclipse-data", RD + "unnamed/brick01_n.png", ["--directx"]),
    ("mine_atlas", "redeclipse-data", RD + "weapons/mine/normals.png", []),
    ("palm_bark", "redeclipse-data", RD + "dziq/meshtex/palm_tree_trunk_n.jpg", ["--directx"]),
    ("brickA", "supertuxkart-data", STK + "textures/stk_generic_brickA_Normal.png", []),
    ("cobblestone", "supertuxkart-data", STK + "textures/stktex_generic_cobbleStoneA_Normal.png", ["--directx"]),
    ("forest_floor", "supertuxkart-data", STK + "tracks/black_forest/grass_forestFloor_big_nm.jpg", []),
    ("karst_rock", "supertuxkart-data", STK + "textures/stk_karstRock_a_nm.jpg", []),
    ("castle_wall", "cube2-data", C2 + "gk/fantasy/castell_wall_gk_v01/castell_wall_gk_v01_nm.jpg", ["--directx"]),
    ("hex_paving", "cube2-data", C2 + "gk/dds/gk_ground_m_01_nm_1024.dds", ["--directx"]),
    ("asteroid", "glmark2-data", "/usr/share/glmark2/textures/asteroid-normal-map-tangent.png", []),
    ("barren_height", "freeorion-data", "/usr/share/games/freeorion/default/data/art/planets/Barren-bump01.png",
     ["--from", "height", "--strength", "8"]),
    ("brick01_height", "redeclipse-data", RD + "unnamed/brick01_z.png", ["--from", "height", "--strength", "8"]),
    ("castle_height", "cube2-data", C2 + "gk/fantasy/castell_wall_gk_v01/castell_wall_gk_v01_hm.jpg",
     ["--from", "height", "--strength", "8"]),
    ("asteroid_height", "glmark2-data", "/usr/share/glmark2/textures/asteroid-height-map.png",
     ["--from", "height", "--strength", "8"]),
]
CORPUS_PACKAGES = sorted({package for _, package, _, _ in CORPUS})
# The plane near its mirror direction (the plane's default light for a map of one's own: the
# view 0,0.3,1 mirrored), the teapot lit from the front (the default light) and from behind.
# (The grazing plane covers no whole pixel of the 256 x 256 frame at 64 radii: 32 is its
# farthest.)
CORPUS_VIEWS = [
    ("plane", ["--scene", "plane", "--view-dir", "0,0.3,1", "--light-dir", "0,0.35,-1",
               "--distances", "1.5,4,16,32"]),
    ("teapot", ["--scene", "teapot", "--distances", "1.5,4,16,64"]),
    ("teapot_back", ["--scene", "teapot", "--light-dir", "0.3,0.4,-1", "--distances", "1.5,4,16,64"]),
]


def corpus_configurations(brdfs):
    """(name, eval arguments, seeds) of every corpus run whose map is installed."""
    runs = []
    # View by view (every map's plane first), so that a partial run covers every map.
    for view, view_flags in CORPUS_VIEWS:
        for tag, _, path, flags in CORPUS:
            if not os.path.exists(path):
                continue
            for brdf, brdf_tag in (("blinn-phong", "bp"), ("cook-torrance", "ct")):
                if brdf_tag not in brdfs:
                    continue
                runs.append((f"corpus_{tag}_{view}_{brdf_tag}",
                             view_flags + ["--bumps", path, "--brdf", brdf] + flags, 1))
    return runs
WRAP = "/usr/share/assimp/models/glTF2/ClearCoat-glTF/PlasticWrap_normals.jpg"


BUILTIN_SETS = ("bumps", "noise", "ridges")


def flag_value(flags, name):
    """The value after flag `name` in an eval argument list, or None."""
    return flags[flags.index(name) + 1] if name in flags else None


def is_height_map(flags):
    return flag_value(flags, "--from") == "height"


def at_texture_sizes(runs, sizes):
    """runs, those of a built-in set once per texture size (`_tSIZE` unless 256)."""
    sized = []
    for name, flags, seeds in runs:
        builtin = flag_value(flags, "--bumps") in BUILTIN_SETS
        for size in (sizes if builtin else [256]):
            if size == 256:  # the default: the configuration as it is
                sized.append((name, flags, seeds))
            else:
                sized.append((f"{name}_t{size}", flags + ["--texture-size", str(size)], seeds))
    return sized


def configurations(seeds):
    """(name, eval arguments, seeds) of every run."""
    runs = []
    for brdf, tag in (("blinn-phong", "bp"), ("cook-torrance", "ct")):
        for aa in ("off", "on"):
            common = ["--brdf", brdf, "--geometric-aa", aa]
            runs.append((f"teapot_bumps_{tag}_aa{aa}", ["--scene", "teapot", "--bumps", "bumps"] + common, seeds))
            runs.append((f"sphere_bumps_{tag}_aa{aa}", ["--scene", "sphere", "--bumps", "bumps"] + common, seeds))
    for aa in ("off", "on"):
        common = ["--geometric-aa", aa]
        runs.append((f"plane_glint_bumps_bp_aa{aa}", PLANE_GLINT + ["--bumps", "bumps", "--distances", "4,16"] + common, seeds))
        runs.append((f"teapot_noise_bp_aa{aa}", ["--scene", "teapot", "--bumps", "noise"] + common, seeds))
        runs.append((f"teapot_ridges_bp_aa{aa}", ["--scene", "teapot", "--bumps", "ridges"] + common, seeds))
        runs.append((f"sphere_flat_bp_aa{aa}", ["--scene", "sphere", "--bumps", "flat"] + common, 1))
    for brdf, tag in (("blinn-phong", "bp"), ("cook-torrance", "ct")):
        for aa in ("off", "on"):
            common = ["--brdf", brdf, "--geometric-aa", aa]
            if tag == "ct":
                runs.append((f"teapot_ridges_ct_aa{aa}", ["--scene", "teapot", "--bumps", "ridges"] + common, seeds))
            for path, map_tag in ((RIBS, "ribs"), (WRAP, "plasticwrap")):
                if os.path.exists(path):
                    runs.append((f"teapot_{map_tag}_{tag}_aa{aa}", ["--scene", "teapot", "--bumps", path] + common, 1))
    return runs


def filament_configurations():
    """(name, eval arguments, normal map) of the Filament peer runs: one per real map."""
    runs = []
    for brdf, brdf_tag in (("blinn-phong", "bp"), ("cook-torrance", "ct")):
        for aa in ("off", "on"):
            for path, tag in ((RIBS, "ribs"), (WRAP, "plasticwrap")):
                if os.path.exists(path):
                    runs.append((f"teapot_{tag}_{brdf_tag}_aa{aa}",
                                 ["--scene", "teapot", "--bumps", path, "--brdf", brdf,
                                  "--geometric-aa", aa], path))
    return runs


def filament_chain(normal_map, shininess, folder):
    """Runs roughness-prefilter on `normal_map` with the base roughness of `shininess`; returns
    the path of its level 0 (NAME_0.png)."""
    os.makedirs(folder, exist_ok=True)
    source = normal_map
    if not normal_map.lower().endswith(".png"):
        source = os.path.join(folder, "normal.png")
        if not os.path.exists(source):
            subprocess.run(["convert", normal_map, source], check=True)
    r0 = (2.0 / shininess) ** 0.25
    out = os.path.join(folder, f"roughness_s{shininess:g}.png")
    subprocess.run(["roughness-prefilter", "--roughness", f"{r0:.6f}", "--linear", source, out],
                   check=True, stdout=subprocess.DEVNULL)
    return os.path.join(folder, f"roughness_s{shininess:g}_0.png")


def result_rows(name, folder, technique=None):
    with open(os.path.join(folder, "results.json")) as f:
        results = json.load(f)
    rows = []
    for c in results["cases"]:
        rows.append({"configuration": name, "technique": technique or c["technique"],
                     "shininess": c["shininess"], "distance": c["distance"],
                     "seeds": c.get("seeds", 1), "energy_total": c.get("energy_total"),
                     "energy": c["energy"], "energy_total_spread": c.get("energy_total_spread"),
                     "rmse": c["rmse"], "flicker": c["flicker"],
                     "reference_energy_error": c.get("reference_energy_error")})
    return rows


def run_eval(command):
    print(" ".join(command), file=sys.stderr, flush=True)
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL,
                   env=dict(os.environ, EGL_PLATFORM="surfaceless"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--leanfade", default="build/tools/leanfade/leanfade")
    parser.add_argument("--out", default="out/bake_off")
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--frames", type=int, default=4)
    parser.add_argument("--only", default="")
    parser.add_argument("--corpus", action="store_true",
                        help="run the real-map corpus (CORPUS) instead of the built-in sets")
    parser.add_argument("--brdfs", default="bp,ct", help="corpus runs: bp, ct or both")
    parser.add_argument("--techniques", default=TECHNIQUES)
    parser.add_argument("--frame-size", type=int, default=256,
                        help="pixels per side of the frame (other than 256: `_fN` names)")
    parser.add_argument("--geometric-aa", choices=["on", "off"],
                        help="corpus runs: every technique with geometric AA on or off")
    parser.add_argument("--texture-sizes", default="256",
                        help="built-in sets: texels per side, e.g. 256,1024,4096")
    parser.add_argument("--peers-only", action="store_true",
                        help="run only the peer rows (Filament's roughness MIPs), not --techniques")
    parser.add_argument("--no-peers", action="store_true",
                        help="skip the peer rows (Filament's roughness MIPs)")
    parser.add_argument("--resume", action="store_true",
                        help="keep the results of configurations already run into --out")
    parser.add_argument("--list-corpus", action="store_true",
                        help="print the installed corpus maps as leanfade_compression_error's "
                             "arguments (--normal MAP | --height MAP) and stop")
    args = parser.parse_args()
    if args.list_corpus:
        for _, _, path, flags in CORPUS:
            if os.path.exists(path):
                print("--height" if is_height_map(flags) else "--normal", path)
        return
    only = set(filter(None, args.only.split(",")))
    os.makedirs(args.out, exist_ok=True)
    rows = []
    sizes = [int(size) for size in args.texture_sizes.split(",")]
    runs = (corpus_configurations(args.brdfs.split(",")) if args.corpus
            else at_texture_sizes(configurations(args.seeds), sizes))
    if args.geometric_aa:
        if not args.corpus:
            sys.exit("bake_off.py: --geometric-aa is for --corpus (the built-in sets name theirs)")
        runs = [(f"{name}_aa{args.geometric_aa}", flags + ["--geometric-aa", args.geometric_aa],
                 seeds) for name, flags, seeds in runs]
    if args.frame_size != 256:
        runs = [(f"{name}_f{args.frame_size}", flags + ["--size", f"{args.frame_size}x{args.frame_size}"],
                 seeds) for name, flags, seeds in runs]
    if args.corpus and not runs:
        sys.exit("bake_off.py: no corpus map is installed (apt-get install " +
                 " ".join(CORPUS_PACKAGES) + ")")
    for name, flags, seeds in runs:
        if (only and name not in only) or args.peers_only:
            continue
        folder = os.path.join(args.out, name)
        if args.resume and os.path.exists(os.path.join(folder, "results.json")):
            rows += result_rows(name, folder)
            continue
        run_eval([args.leanfade, "eval", "--techniques", args.techniques, "--frames", str(args.frames),
                  "--seeds", str(seeds), "--out", folder] + flags)
        rows += result_rows(name, folder)
    # The peer: Filament's roughness MIPs as the roughness technique's input, per shininess.
    # On the corpus: every configuration of a normal map (a height map has no normal map file).
    peers = ([(name, flags, flag_value(flags, "--bumps")) for name, flags, _ in runs
              if not is_height_map(flags)] if args.corpus else filament_configurations())
    if shutil.which("roughness-prefilter") and not args.no_peers:
        for name, flags, normal_map in peers:
            if only and name not in only:
                continue
            for shininess in (128, 1024, 13777):
                chain = filament_chain(normal_map, shininess,
                                       os.path.join(args.out, "filament",
                                                    normal_map.strip("/").replace("/", "_")))
                folder = os.path.join(args.out, name, f"filament_s{shininess}")
                run_eval([args.leanfade, "eval", "--techniques", "roughness", "--frames",
                          str(args.frames), "--shininess", str(shininess), "--roughness-mips",
                          chain, "--out", folder] + flags)
                rows += result_rows(name, folder, "roughness (Filament)")
    if not rows:
        sys.exit("bake_off.py: no configuration selected")
    write_rows(rows, os.path.join(args.out, "bake_off"))
    with open(os.path.join(args.out, "bake_off.md"), "w") as f:
        f.write(markdown(rows))
    print(os.path.join(args.out, "bake_off.md"))


def write_rows(rows, stem):
    """rows (dicts with the same keys) as STEM.json and STEM.csv."""
    with open(stem + ".json", "w") as f:
        json.dump(rows, f, indent=1)
    with open(stem + ".csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)


def fmt(v, digits=2):
    return "?" if v is None or v != v else f"{v:.{digits}f}"


def markdown(rows):
    """One table per configuration: a row per (technique, shininess), energy_total (masked
    energy) per distance, then the RMSE and flicker at the farthest distance."""
    out = []
    for name in dict.fromkeys(r["configuration"] for r in rows):
        cases = [r for r in rows if r["configuration"] == name]
        distances = sorted({r["distance"] for r in cases})
        seeds = cases[0]["seeds"]
        out.append(f"\n**{name}** ({seeds} bump map{'s' if seeds > 1 else ''}; energy over every "
                   f"covered pixel, masked in parentheses; RMSE and flicker at {distances[-1]:g} radii)\n")
        out.append("| technique | s | " + " | ".join(f"{d:g}" for d in distances) + " | RMSE | flicker |")
        out.append("|---|---|" + "---|" * (len(distances) + 2))
        for technique in dict.fromkeys(r["technique"] for r in cases):
            for s in sorted({r["shininess"] for r in cases}):
                row = {r["distance"]: r for r in cases if r["technique"] == technique and r["shininess"] == s}
                far = row[distances[-1]]
                cells = [f"{fmt(row[d]['energy_total'])} ({fmt(row[d]['energy'])})" for d in distances]
                out.append(f"| {technique} | {s:g} | " + " | ".join(cells) +
                           f" | {fmt(far['rmse'])} | {fmt(far['flicker'])} |")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    main()
