#pragma once
// leanfade for engines: everything an asset pipeline or a renderer needs to make and load LEAN
// maps, without OpenGL (find_package(leanfade) -> leanfade::leanfade, or pkg-config leanfade;
// docs/integration.md).
//
//   Bake             leanfade::bake(BakeInput(image, source), BakeSettings{options, storage,
//                    generator}, sink) -> PackedBakeResult; the sink says where the map goes:
//                    PackedMapSink (memory: result.packed, a PackedLeanMap of every MIP level's
//                    layers, packed as the GPU samples them, docs/math.md §3, and sc),
//                    io::Ktx2FileSink (a KTX2 file written in place), LevelTargetsSink (memory
//                    the caller provides), MomentsOnlySink (the float moments only).
//   Images           leanfade::io::read_image / read_image_from_memory (PNG, OpenEXR, PFM), or an
//                    Image filled by the caller (height map: 1 channel; normal map: 3 channels).
//   KTX2             leanfade::io::write_ktx2 / write_ktx2_to_memory, read_ktx2 /
//                    read_ktx2_from_memory, inspect_ktx2 (docs/ktx2.md).
//   Shading on CPU   leanfade::shading::lf_unpack, lf_shade: the functions of the GLSL shaders
//                    (shaders/lean_shading.glsl), compiled as C++ with glm.
//   Techniques       leanfade::kTechniques: each technique's LF_TECHNIQUE_* value and the
//                    textures it reads.
//   Version          LEANFADE_VERSION_MAJOR / _MINOR / _PATCH / _STRING (leanfade/version.hpp).
// Every failure throws leanfade::Error (what(): "<file or setting>: <cause>").
#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/shading.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/version.hpp"
