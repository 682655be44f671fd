#pragma once
// Command-line flags of the settings that the libraries name in their errors. The libraries say
// "shininess: must be > 0"; the command line says "--shininess: must be > 0".
#include <string>
#include <string_view>

#include "leanfade/core/error.hpp"

namespace leanfade::cli {

// The flag of a setting: "--" and the name with '-' for '_' ("fade_exponent" ->
// "--fade-exponent"), but for the few flags with shorter names ("light_direction" ->
// "--light-dir"); "" when `name` is no setting (a file name, "GL", ...).
std::string flag_for_setting(std::string_view name);

// `error` with its subject replaced by the flag when it names a setting.
Error with_flag_name(const Error& error);

}  // namespace leanfade::cli
