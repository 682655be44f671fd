// Sweeps over several bump maps combined into one (leanfade/eval/results.hpp, combine_seeds).
#include <cmath>
#include <string>

#include "leanfade/core/error.hpp"
#include "leanfade/eval/results.hpp"

namespace leanfade::eval {
namespace {

double ratio(double num, double den) {
    return den > 0.0 ? num / den : std::nan("");
}

// Standard deviation of the finite values (0 for fewer than two).
double spread(const std::vector<double>& values) {
    double sum = 0.0, squares = 0.0;
    int n = 0;
    for (double v : values)
        if (std::isfinite(v)) {
            sum += v;
            squares += v * v;
            ++n;
        }
    if (n < 2) return 0.0;
    const double mean = sum / n;
    return std::sqrt(std::max(0.0, (squares - n * mean * mean) / (n - 1)));
}

}  // namespace

std::vector<CaseResult> combine_seeds(const std::vector<std::vector<CaseResult>>& sweeps) {
    if (sweeps.empty()) throw Error::setting("seeds", "no sweep to combine");
    const std::vector<CaseResult>& first = sweeps.front();
    for (const std::vector<CaseResult>& sweep : sweeps) {
        if (sweep.size() != first.size())
            throw Error::setting("seeds", "the sweeps hold different numbers of cases");
        for (std::size_t i = 0; i < sweep.size(); ++i)
            if (sweep[i].technique != first[i].technique ||
                sweep[i].distance != first[i].distance || sweep[i].shininess != first[i].shininess)
                throw Error::setting("seeds", "the sweeps hold different cases");
    }
    std::vector<CaseResult> combined;
    for (std::size_t i = 0; i < first.size(); ++i) {
        CaseResult c = first[i];
        double masked = 0.0, reference_masked = 0.0, total = 0.0, reference_total = 0.0;
        double rmse = 0.0, ssim = 0.0, flicker = 0.0, change = 0.0, reference_change = 0.0;
        int flicker_count = 0;
        std::vector<double> energies, totals;
        for (const std::vector<CaseResult>& sweep : sweeps) {
            const CaseResult& s = sweep[i];
            masked += s.specular_mean * s.object_pixels;
            reference_masked += s.reference_specular_mean * s.object_pixels;
            total += s.specular_total;
            reference_total += s.reference_specular_total;
            rmse += s.rmse;
            ssim += s.ssim;
            change += s.change;
            reference_change += s.reference_change;
            if (std::isfinite(s.flicker)) {
                flicker += s.flicker;
                ++flicker_count;
            }
            energies.push_back(s.energy);
            totals.push_back(s.energy_total);
        }
        const double n = double(sweeps.size());
        c.seeds = int(sweeps.size());
        c.energy = ratio(masked, reference_masked);
        c.energy_total = ratio(total, reference_total);
        c.specular_total = total / n;
        c.reference_specular_total = reference_total / n;
        c.energy_spread = spread(energies);
        c.energy_total_spread = spread(totals);
        c.rmse = rmse / n;
        c.ssim = ssim / n;
        c.change = change / n;
        c.reference_change = reference_change / n;
        c.flicker = flicker_count > 0 ? flicker / flicker_count : std::nan("");
        combined.push_back(c);
    }
    return combined;
}

}  // namespace leanfade::eval
