// Fuzz target: the gnuplot scripts leanfade writes and runs (`eval`'s plots.gp from the technique
// names of a results.json, `calibrate`'s from its --plot file name and target). Arbitrary strings
// become technique names, titles and file names; the oracle parses each script with a small
// tokenizer and fails when any line is not one of the commands leanfade writes (set, unset,
// plot, a comment), when a string literal is not closed on its line, when anything outside a
// string could start a second command or a substitution (';', '`', '@', '"', a continuation
// '\'), or when a file position (set output, a plot's data file) could name a pipe ('<', '|').
// Accepted file names must come back unchanged, behind "./" when relative.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/eval/calibration.hpp"
#include "leanfade/eval/results.hpp"

namespace {

[[noreturn]] void finding() {
    __builtin_trap();
}

// One script line as the tokens the oracle cares about: the string literals (decoded) and, for
// each, whether it stands where gnuplot reads a file name.
struct Line {
    std::string command;  // first word
    std::vector<std::string> strings;
    std::vector<bool> file_position;
};

bool is_control(char c) {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
}

// Parses a line outside strings; calls finding() for anything a leanfade script never holds.
Line parse_line(const std::string& line) {
    Line out;
    std::size_t i = 0;
    while (i < line.size() && line[i] != ' ') ++i;
    out.command = line.substr(0, i);
    if (out.command != "set" && out.command != "unset" && out.command != "plot") finding();
    std::string before = out.command;  // the code before the current string: its position
    while (i < line.size()) {
        const char c = line[i];
        if (c == '\'') {
            std::string text;
            ++i;
            bool closed = false;
            while (i < line.size()) {
                if (line[i] == '\'') {
                    if (i + 1 < line.size() && line[i + 1] == '\'') {
                        text += '\'';
                        i += 2;
                        continue;
                    }
                    closed = true;
                    ++i;
                    break;
                }
                if (is_control(line[i])) finding();  // cuts or ends the command
                text += line[i++];
            }
            if (!closed) finding();
            // A file: after "set output", or a plot's data file (followed by index or using).
            const bool output = before == "set output ";
            const std::string rest = line.substr(i, 7);
            const bool data = rest.rfind(" index", 0) == 0 || rest.rfind(" using", 0) == 0;
            out.strings.push_back(text);
            out.file_position.push_back(output || data);
            before += "S";
            continue;
        }
        if (c == ';' || c == '`' || c == '@' || c == '"' || c == '#' || is_control(c)) finding();
        before += c;
        ++i;
    }
    if (!line.empty() && line.back() == '\\') finding();  // would continue onto the next line
    for (std::size_t s = 0; s < out.strings.size(); ++s)
        if (out.file_position[s]) {
            const std::string& f = out.strings[s];
            if (f.empty() || f[0] == '<' || f[0] == '|' || f[0] == '-') finding();
        }
    return out;
}

// Every line; returns the parsed commands (comments and blank lines skipped).
std::vector<Line> parse_script(const std::string& script) {
    std::vector<Line> lines;
    std::size_t start = 0;
    while (start < script.size()) {
        std::size_t end = script.find('\n', start);
        if (end == std::string::npos) finding();  // every line ends with a newline
        const std::string line = script.substr(start, end - start);
        start = end + 1;
        if (line.empty() || line[0] == '#') continue;
        lines.push_back(parse_line(line));
    }
    return lines;
}

void check_file_literal(const std::string& name) {
    std::string literal;
    try {
        literal = leanfade::eval::gnuplot_file(name);
    } catch (const leanfade::Error&) {
        return;
    }
    const Line line = parse_line("set output " + literal);
    if (line.strings.size() != 1) finding();
    const std::string expected = name[0] == '/' ? name : "./" + name;
    if (line.strings[0] != expected) finding();  // a file name is never changed
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);

    // eval's plots: up to 6 techniques (any row of the table, repeats allowed), 1 to 3
    // shininesses, 1 to 3 distances.
    std::vector<leanfade::eval::CaseResult> cases;
    std::vector<leanfade::Technique> techniques;
    const int technique_count = in.ConsumeIntegralInRange(1, 6);
    for (int t = 0; t < technique_count; ++t)
        techniques.push_back(leanfade::Technique(
            in.ConsumeIntegralInRange<std::size_t>(0, leanfade::kTechniques.size() - 1)));
    std::vector<float> shininesses;
    const int panels = in.ConsumeIntegralInRange(1, 3);
    for (int s = 0; s < panels; ++s) shininesses.push_back(in.ConsumeFloatingPoint<float>());
    const int distances = in.ConsumeIntegralInRange(1, 3);
    for (int s = 0; s < panels; ++s)
        for (int d = 0; d < distances; ++d)
            for (const leanfade::Technique technique : techniques) {
                leanfade::eval::CaseResult c;
                c.technique = technique;
                c.shininess = shininesses[std::size_t(s)];
                c.distance = in.ConsumeFloatingPoint<float>();
                c.energy = in.ConsumeFloatingPoint<double>();
                cases.push_back(c);
            }
    const std::vector<Line> plots = parse_script(leanfade::eval::plots_script(cases, shininesses));
    // One picture per metric (a "set output"), one plot per shininess in each: any other count
    // means a string added or cut a command.
    std::size_t plot_lines = 0, outputs = 0;
    for (const Line& line : plots) {
        plot_lines += line.command == "plot" ? 1 : 0;
        outputs += line.command == "set" && !line.file_position.empty() && line.file_position[0];
    }
    if (outputs == 0 || plot_lines != outputs * shininesses.size()) finding();

    // calibrate's plot: the target's name, the plot and data file names.
    const std::string target = in.ConsumeRandomLengthString(64);
    const std::string plot_file = in.ConsumeRandomLengthString(64);
    const std::string data_file = in.ConsumeRandomLengthString(64);
    const double fade = in.ConsumeFloatingPoint<double>();
    const double pmax = in.ConsumeFloatingPoint<double>();
    const std::vector<double> values = {in.ConsumeFloatingPoint<double>(),
                                        in.ConsumeFloatingPoint<double>()};
    check_file_literal(plot_file);
    check_file_literal(data_file);
    try {
        const std::vector<Line> calibration = parse_script(leanfade::eval::calibration_plot_script(
            target, fade, pmax, values, values, plot_file, data_file));
        std::size_t plot_count = 0;
        for (const Line& line : calibration) plot_count += line.command == "plot" ? 1 : 0;
        if (plot_count != 1) finding();
    } catch (const leanfade::Error&) {
        // a file name gnuplot cannot be given: refused, as documented
    }
    return 0;
}
