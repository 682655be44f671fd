#!/usr/bin/env python3
"""Instruction counts of the fragment stages of leanfade's techniques (docs/perf.md).

Resolves shaders/<file> the way libs/gl/src/shader_library.cpp does (#include "x" inlined once,
the variant's #defines after #version), compiles each variant to SPIR-V with glslangValidator
(uniforms moved into a default block with --auto-map-locations and relaxed Vulkan rules), runs
spirv-opt -O and counts the instructions of the optimised main function: arithmetic (ALU),
extended instructions (exp, pow, sqrt, normalize ... each one instruction, as a GPU ISA would
expand them further), texture samples and branches. SPIR-V is a portable proxy, not a driver's
ISA: the papers' counts (LEAN: 30 ALU + 1 tex Blinn-Phong, 42 ALU + 2 tex LEAN) were a Radeon
HD 5870's.

usage: scripts/shader-stats.py [VARIANT=DEFINE[,DEFINE]] ...
       default: the constant-colour floor, then the real-time techniques as the renderer draws
       ordinary frames (LF_PLAIN_COLOR) and in general (debug outputs and fog selectable)
"""
import collections
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHADERS = os.path.join(ROOT, "shaders")

# The programs of ordinary frames (the renderer's "_plain" variants), then the general ones.
DEFAULT_VARIANTS = [("floor", "constant.frag", [])] + [
    (t + suffix, "scene.frag", ["TECHNIQUE_" + t.upper()] + defines)
    for suffix, defines in (("", ["LF_PLAIN_COLOR"]), ("/general", []))
    for t in ("bump", "toksvig", "clean", "lean", "fade")
]

TEXTURE_OPS = {"OpImageSampleImplicitLod", "OpImageSampleExplicitLod", "OpImageFetch",
               "OpImageSampleDrefImplicitLod", "OpImageGather"}
BRANCH_OPS = {"OpBranchConditional", "OpSwitch"}
MEMORY_OPS = {"OpLoad", "OpStore", "OpAccessChain", "OpVariable", "OpInBoundsAccessChain"}
STRUCTURE_OPS = {"OpLabel", "OpBranch", "OpSelectionMerge", "OpLoopMerge", "OpReturn",
                 "OpReturnValue", "OpFunction", "OpFunctionEnd", "OpFunctionParameter",
                 "OpPhi", "OpKill", "OpUnreachable", "OpLine", "OpNoLine"}
COMPOSITE_OPS = {"OpCompositeConstruct", "OpCompositeExtract", "OpVectorShuffle",
                 "OpCompositeInsert", "OpCopyObject", "OpSampledImage", "OpImage"}


def resolve(name, defines, seen=None, main=True):
    seen = seen if seen is not None else set()
    out = []
    with open(os.path.join(SHADERS, name)) as f:
        lines = f.read().split("\n")
    for i, line in enumerate(lines):
        if main and i == 0:
            out.append(line)
            out.extend("#define " + d for d in defines)
            continue
        m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
        if m:
            if m.group(1) not in seen:
                seen.add(m.group(1))
                out.append(resolve(m.group(1), [], seen, False))
            continue
        out.append(line)
    return "\n".join(out)


def count(file, defines):
    text = resolve(file, defines)
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "shader.frag")
        with open(src, "w") as f:
            f.write(text)
        spv, opt = os.path.join(tmp, "a.spv"), os.path.join(tmp, "o.spv")
        subprocess.run(["glslangValidator", "-G", "--auto-map-locations", "--auto-map-bindings",
                        "-S", "frag", "-o", spv, src], check=True, stdout=subprocess.DEVNULL)
        subprocess.run(["spirv-opt", "-O", spv, "-o", opt], check=True)
        dis = subprocess.run(["spirv-dis", "--raw-id", opt], check=True, capture_output=True,
                             text=True).stdout
    ops = collections.Counter()
    ext = collections.Counter()
    in_function = False
    for line in dis.split("\n"):
        m = re.match(r"\s*(?:%\w+ = )?(Op\w+)(.*)", line)
        if not m:
            continue
        op, rest = m.group(1), m.group(2)
        if op == "OpFunction":
            in_function = True
        if not in_function:
            continue
        if op == "OpExtInst":
            ext[rest.split()[2]] += 1
        ops[op] += 1
        if op == "OpFunctionEnd":
            in_function = False
    tex = sum(ops[o] for o in TEXTURE_OPS)
    branches = sum(ops[o] for o in BRANCH_OPS)
    alu = sum(n for o, n in ops.items()
              if o not in TEXTURE_OPS | BRANCH_OPS | MEMORY_OPS | STRUCTURE_OPS | COMPOSITE_OPS)
    return alu, tex, branches, ext


def main(argv):
    variants = DEFAULT_VARIANTS
    if argv:
        variants = []
        for arg in argv:
            name, _, defines = arg.partition("=")
            variants.append((name, "scene.frag", [d for d in defines.split(",") if d]))
    print(f"{'variant':15} {'ALU':>4} {'tex':>4} {'branch':>6}  extended instructions")
    for name, file, defines in variants:
        try:
            alu, tex, branches, ext = count(file, defines)
        except (subprocess.CalledProcessError, FileNotFoundError) as e:
            print(f"{name:15} failed: {e}")
            continue
        extended = ", ".join(f"{k} {v}" for k, v in sorted(ext.items()))
        print(f"{name:15} {alu:4} {tex:4} {branches:6}  {extended}")


if __name__ == "__main__":
    main(sys.argv[1:])
