// Results files of `leanfade eval`: the gnuplot scripts and the plots.
#include "leanfade/eval/results.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "results_internal.hpp"

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/eval/metrics.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::eval {

using namespace results_detail;

bool run_gnuplot(const std::string& script_path, std::string& note) {
    if (!executable_on_path("gnuplot")) {
        note =
            "gnuplot not found on PATH (Debian: apt install gnuplot-nox): plots not drawn; "
            "the data and the script " +
            script_path + " are written";
        return false;
    }
    // gnuplot itself, no shell: the script is a file argument ("./" keeps a name starting with
    // '-' from being an option), run in the script's folder, its output read from a pipe.
    const fs::path script(script_path);
    const std::string folder = script.parent_path().empty() ? "." : script.parent_path().string();
    const std::string argument = "./" + script.filename().string();
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) {
        note = "could not start gnuplot (no pipe)";
        return false;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
    posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
    posix_spawn_file_actions_addchdir_np(&actions, folder.c_str());
    char* const argv[] = {const_cast<char*>("gnuplot"), const_cast<char*>(argument.c_str()),
                          nullptr};
    pid_t pid = 0;
    const int spawned = ::posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(fds[1]);
    if (spawned != 0) {
        ::close(fds[0]);
        note = "could not start gnuplot: " + std::string(std::strerror(spawned));
        return false;
    }
    std::string output;
    char buffer[512];
    for (;;) {
        const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
        if (n > 0) {
            if (output.size() < 4096) output.append(buffer, std::size_t(n));
        } else if (n == 0 || errno != EINTR) {
            break;
        }
    }
    ::close(fds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::replace_if(output.begin(), output.end(), is_control, ' ');
        note = "gnuplot failed on " + script_path + ": " + output.substr(0, 300);
        return false;
    }
    return true;
}

bool write_plots(const std::string& folder, const std::vector<CaseResult>& cases,
                 const std::vector<float>& shininesses, std::string& note) {
    const std::vector<Technique> techniques = technique_order(cases);
    // plot_data.tsv: one block per (shininess, technique), blocks separated by two blank lines
    // (gnuplot's `index`), in that order.
    std::ostringstream data;
    data << "# distance";
    for (const Metric& metric : metrics()) data << " " << metric.key;
    data << " reference_noise; one block per (shininess, technique)\n";
    for (float s : shininesses)
        for (Technique t : techniques) {
            const std::string name = to_string(t);
            data << "# shininess " << short_number(s) << " technique " << name << "\n";
            std::vector<const CaseResult*> rows;
            for (const CaseResult& c : cases)
                if (c.shininess == s && c.technique == t) rows.push_back(&c);
            std::sort(rows.begin(), rows.end(), [](const CaseResult* a, const CaseResult* b) {
                return a->distance < b->distance;
            });
            for (const CaseResult* c : rows) {
                data << number(c->distance);
                std::vector<double> values;
                for (const Metric& metric : metrics()) values.push_back(c->*metric.field);
                values.push_back(c->reference_noise);
                for (double v : values)
                    data << "\t" << (std::isfinite(v) ? number(v) : std::string("?"));
                data << "\n";
            }
            data << "\n\n";
        }
    write_text_file((fs::path(folder) / "plot_data.tsv").string(), data.str());
    const std::string script = (fs::path(folder) / "plots.gp").string();
    write_text_file(script, plots_script(cases, shininesses));
    return run_gnuplot(script, note);
}

std::string plots_script(const std::vector<CaseResult>& cases,
                         const std::vector<float>& shininesses) {
    const std::vector<Technique> techniques = technique_order(cases);
    const std::string data = gnuplot_file("plot_data.tsv");
    std::ostringstream gp;
    const int panels = int(shininesses.size());
    float lo = 0.0f, hi = 0.0f;
    for (const CaseResult& c : cases) {
        if (!(std::isfinite(c.distance) && c.distance > 0.0f)) continue;
        lo = lo == 0.0f ? c.distance : std::min(lo, c.distance);
        hi = std::max(hi, c.distance);
    }
    if (lo == 0.0f) lo = hi = 1.0f;
    gp << "# gnuplot script written by leanfade eval; run `gnuplot plots.gp` in this folder.\n"
       << "set datafile missing '?'\nset datafile separator '\\t'\n"
       << "set logscale x 2\nset grid\nset format y '%g'\n"
       << "set xlabel " << gnuplot_string("camera distance (bounding radii)") << "\n"
       << "set xrange [" << lo / 1.15f << ":" << hi * 1.15f << "]\n";
    for (std::size_t m = 0; m < metrics().size(); ++m) {
        const Metric& metric = metrics()[m];
        gp << "\nset terminal pngcairo size " << 360 * panels + 40 << ",360 font 'sans,10'\n"
           << "set output " << gnuplot_file(std::string(metric.key) + ".png") << "\n"
           << "set multiplot layout 1," << panels << " title " << gnuplot_string(metric.title)
           << "\n"
           << (metric.log_y ? "set logscale y\n" : "unset logscale y\n") << "set yrange "
           << metric.y_range << "\n"
           << "set ylabel " << gnuplot_string(metric.y_label) << "\n";
        for (int si = 0; si < panels; ++si) {
            // One key, in the first panel.
            gp << (si == 0 ? "set key top left opaque box font ',8' samplen 2 spacing 0.9\n"
                           : "unset key\n")
               << "set title "
               << gnuplot_string("s = " + short_number(shininesses[std::size_t(si)])) << "\n"
               << "plot ";
            if (std::isfinite(metric.truth))
                gp << metric.truth << " with lines dt 2 lc rgb '#808080' title 'reference', ";
            if (metric.field == &CaseResult::rmse)  // the floor the reference's noise sets
                gp << data << " index " << std::size_t(si) * techniques.size()
                   << " using 1:" << metrics().size() + 2
                   << " with lines dt 2 lw 2 lc rgb '#808080' title 'reference noise', ";
            for (std::size_t ti = 0; ti < techniques.size(); ++ti) {
                const std::size_t block = std::size_t(si) * techniques.size() + ti;
                gp << (ti == 0 ? "" : ", ") << data << " index " << block << " using 1:" << m + 2
                   << " with linespoints lw 2 pt 7 ps 0.6 lc rgb "
                   << gnuplot_string(technique_color(techniques[ti])) << " title "
                   << gnuplot_string(to_string(techniques[ti]));
            }
            gp << "\n";
        }
        gp << "unset multiplot\n";
    }
    return gp.str();
}

}  // namespace leanfade::eval
