#pragma once
// Command-line flags of the settings that the libraries name in their errors (the libraries say
// "shininess: must be > 0"; the command line says "--shininess: must be > 0"), and the lines
// that word what the libraries report as data (repaired normals, convention doubts), shared by
// every subcommand.
#include <string>
#include <string_view>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/scene/scene_source.hpp"

namespace leanfade::cli {

// The flag of a setting id: "--" and the id with '-' for '_' ("fade_exponent" ->
// "--fade-exponent"), but for the few flags with shorter names ("light_direction" ->
// "--light-dir"); an id that is a flag already ("--from") as it is.
std::string flag_for_setting(std::string_view id);

// `error` worded for the command line: a setting error's subject is its flag, and the settings
// its cause quotes by id (Error::mentioned_settings: 'strict_normals') are their flags
// (--strict-normals). A file error keeps its file. Nothing is read from the sentence itself.
Error with_flag_name(const Error& error);

// The one line that reports what a bake repaired in a normal map (NormalRepairs):
// "NAME: 12 (0, 0, 0) padding texels taken as flat, 5 texels with z <= 0 raised".
std::string normal_repairs_note(const std::string& name, const NormalRepairs& repairs);

// The warning for a normal map that fits the other convention better (check_normal_convention):
// "NAME looks like a DirectX (-Y) normal map (...); bake it with --directx if ...". `directx`:
// the convention it was read in.
std::string convention_warning(const std::string& name, bool directx, double ratio);

// The warning for a glTF normal texture that looks like a DirectX (-Y) normal map (glTF's are
// OpenGL, +Y, by the specification: --directx does not apply).
std::string gltf_convention_warning(const std::string& image);

// Prints what a build found (scene::SceneSourceReport) as "leanfade: ..." lines on stderr: the
// scene file's warnings, the normal maps' repaired texels and the convention doubts.
void print_scene_report(const std::string& scene_file, const scene::SceneSourceReport& report);

}  // namespace leanfade::cli
