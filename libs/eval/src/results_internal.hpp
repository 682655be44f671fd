#pragma once
// What the results files' sources share (not installed): number text, technique order and
// colours, the metrics' table, file names, and text made safe for the terminal (results.cpp).
// results_files.cpp writes and reads CSV and JSON, results_plots.cpp the gnuplot scripts and
// plots, results_report.cpp the HTML report.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "leanfade/eval/results.hpp"

namespace leanfade::eval::results_detail {

namespace fs = std::filesystem;

// Rounds to `digits` significant digits, so that log-spaced distances print as 3.17 rather than
// 3.1748.
float round_significant(double v, int digits = 3);


std::string number(double v);

// A distance or shininess as it appears in file names and labels: "3.17", "1024".
std::string short_number(double v);

nlohmann::json json_number(double v);

std::string html_escape(const std::string& text);

// Fixed colours per technique, the same in every plot.
std::string technique_color(Technique technique);

std::vector<Technique> technique_order(const std::vector<CaseResult>& cases);

const CaseResult* find_case(const std::vector<CaseResult>& cases, Technique technique,
                            float distance, float shininess);

struct Metric {
    const char* key;    // file name and column
    const char* title;  // plot title
    const char* y_label;
    bool log_y;
    double truth;         // the reference's value (a dashed line), NaN for none
    const char* y_range;  // gnuplot range; values outside are clipped (named in the title)
    double CaseResult::*field;
};

const std::vector<Metric>& metrics();

std::string image_name(float shininess, float distance, Technique technique);

bool executable_on_path(const std::string& name);

bool is_control(char c);

// A name read from a file, for a one-line message: control characters as '?', at most 40
// characters.
std::string printable(const std::string& text);

// After parsing: every technique one the renderer knows, every distance and shininess finite
// and positive (they reach the plots' script and the report).
void validate_results(const std::string& path, const SweepInfo& info,
                      const std::vector<CaseResult>& cases);

}  // namespace leanfade::eval::results_detail
