#!/usr/bin/env python3
"""The corpus table of docs/results.md §9 from bake_off.py's rows.

Reads one or more bake_off.json files (later files replace the rows of the same configuration
and technique), keeps the cases whose truth is converged (reference_energy_error <= 5 %), and
writes per map and view the min-max of energy_total per technique over shininess and distance,
and how many of the recommended technique's cases lie within 0.8-1.25, as Markdown (stdout) and
as CSV/JSON next to --out.

With --below TECHNIQUE, a further column counts the recommended technique's cases that keep
more than 5 % less energy than TECHNIQUE and are also farther from the truth (|ln energy|
larger), over the cases where both ran.

Usage: scripts/corpus_summary.py ROWS.json [MORE.json ...] [--out STEM] [--techniques LIST]
                                 [--below lean] [--skip-maps TAG,...]
"""
import argparse
import csv
import json
import math
import re

LOW, HIGH, CONVERGED = 0.8, 1.25, 0.05


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rows", nargs="+")
    parser.add_argument("--out", default="")
    parser.add_argument("--techniques", default="two-lobe,lean,toksvig,roughness,bump")
    parser.add_argument("--skip-maps", default="",
                        help="leave out these maps (tags, comma-separated), e.g. the height maps")
    parser.add_argument("--below", default="",
                        help="count the first technique's cases > 5 %% below this one's and farther")
    args = parser.parse_args()
    techniques = args.techniques.split(",")
    skipped = set(filter(None, args.skip_maps.split(",")))
    cases = {}
    for path in args.rows:
        with open(path) as f:
            for r in json.load(f):
                key = (r["configuration"], r["technique"], r["shininess"], r["distance"])
                cases[key] = r
    table = {}
    for (configuration, technique, _, _), r in cases.items():
        match = re.fullmatch(
            r"corpus_(.+)_(plane|teapot|teapot_back)_(bp|ct)(_aa(?:on|off))?(_f\d+)?", configuration)
        if not match or technique not in techniques or match.group(1) in skipped:
            continue
        error = r.get("reference_energy_error")
        energy = r.get("energy_total")
        if error is None or error > CONVERGED or energy is None or energy != energy:
            continue
        # A frame size other than 256 (`_f192`) and geometric AA set for every technique
        # (`_aaoff`) make a view of its own.
        view = (match.group(2) + (f" AA {match.group(4)[3:]}" if match.group(4) else "") +
                (f" {match.group(5)[2:]}²" if match.group(5) else ""))
        # Per map, view and BRDF: each case's energy by (technique, shininess, distance).
        table.setdefault((match.group(1), view, match.group(3)), {})[
            (technique, r["shininess"], r["distance"])] = energy
    rows = []
    for (tag, view, brdf), entry in sorted(table.items()):
        row = {"map": tag, "view": view, "brdf": brdf}
        for t in techniques:
            values = energies(entry, t)
            row[t] = f"{min(values):.2f}-{max(values):.2f}" if values else "-"
        first = energies(entry, techniques[0])
        row["within"] = f"{sum(LOW <= v <= HIGH for v in first)}/{len(first)}"
        if args.below:
            below, both = below_count(entry, techniques[0], args.below)
            row["below"] = f"{below}/{both}"
        rows.append(row)
    header = ["map", "view", "brdf"] + techniques + [f"in {LOW}-{HIGH} ({techniques[0]})"]
    if args.below:
        header.append(f"> 5 % below {args.below} and farther")
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for row in rows:
        print("| " + " | ".join(str(v) for v in row.values()) + " |")
    # Totals over every map, then per view and BRDF.
    groups = {"": list(table.values())}
    for (_, view, brdf), entry in sorted(table.items(), key=lambda item: item[0][1:]):
        groups.setdefault(f"{view}, {brdf}", []).append(entry)
    for group, entries in groups.items():
        totals = {t: [0, 0] for t in techniques}
        for entry in entries:
            for t in techniques:
                values = energies(entry, t)
                totals[t][0] += sum(LOW <= v <= HIGH for v in values)
                totals[t][1] += len(values)
        print()
        print((f"{group}: " if group else "") +
              "; ".join(f"{t}: {a} of {b} converged cases within {LOW}-{HIGH}"
                        for t, (a, b) in totals.items()))
        if args.below:
            counts = [below_count(entry, techniques[0], args.below) for entry in entries]
            print(f"{techniques[0]} more than 5 % below {args.below} and farther from the truth: "
                  f"{sum(c[0] for c in counts)} of {sum(c[1] for c in counts)} cases where both "
                  "ran")
    if args.out:
        with open(args.out + ".json", "w") as f:
            json.dump(rows, f, indent=1)
        with open(args.out + ".csv", "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            writer.writeheader()
            writer.writerows(rows)


def energies(by_case, technique):
    """The energies of `technique`'s cases in one map, view and BRDF's table entry."""
    return [energy for (t, _, _), energy in by_case.items() if t == technique]


def below_count(by_case, first, other):
    """(cases where `first` keeps < 0.95 of `other`'s energy and |ln energy| is larger, cases of
    both) over the (shininess, distance) cases both techniques have."""
    below = both = 0
    for (technique, shininess, distance), energy in by_case.items():
        if technique != first or (other, shininess, distance) not in by_case:
            continue
        reference = by_case[(other, shininess, distance)]
        both += 1
        if (energy > 0 and reference > 0 and energy < 0.95 * reference and
                abs(math.log(energy)) > abs(math.log(reference))):
            below += 1
    return below, both


if __name__ == "__main__":
    main()
