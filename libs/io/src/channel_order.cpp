// Which channels of a file are returned, in which order (formats.hpp, order_channels). Compiled
// into leanfade_io and into the OpenImageIO module.
#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

#include "formats.hpp"
#include "leanfade/core/error.hpp"

namespace leanfade::io::detail {

std::vector<int> order_channels(const std::string& path, const std::vector<std::string>& names,
                                const std::string& format_name) {
    std::vector<std::string> bases;
    for (const std::string& name : names) {
        const std::size_t dot = name.rfind('.');
        bases.push_back(dot == std::string::npos ? name : name.substr(dot + 1));
    }
    const auto has = [&](const char* upper, const char* lower) {
        return std::any_of(bases.begin(), bases.end(),
                           [&](const std::string& b) { return b == upper || b == lower; });
    };
    // A normal's components: X and Z present (Y is then y, not luminance).
    const bool xyz = has("X", "x") && has("Z", "z");
    const auto rank = [&](const std::string& b) {
        const auto is = [&](const char* upper, const char* lower) {
            return b == upper || b == lower;
        };
        if (xyz) {
            if (is("X", "x")) return 0;
            if (is("Y", "y")) return 1;
            if (is("Z", "z")) return 2;
        } else {
            if (is("R", "r") || is("Y", "y")) return 0;
            if (is("G", "g")) return 1;
            if (is("B", "b")) return 2;
        }
        if (is("A", "a")) return 3;
        return 4;
    };
    std::vector<int> ranks;
    for (const std::string& b : bases) ranks.push_back(rank(b));
    std::vector<int> order(names.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return ranks[std::size_t(a)] < ranks[std::size_t(b)]; });
    if (order.size() > 4) {
        order.erase(std::remove_if(order.begin(), order.end(),
                                   [&](int i) { return ranks[std::size_t(i)] >= 4; }),
                    order.end());
        if (order.empty() || order.size() > 4) {
            throw Error(path, format_name + " with " + std::to_string(names.size()) +
                                  " channels and no R, G, B, A or X, Y, Z subset (at most 4 "
                                  "supported)");
        }
    }
    if (order.empty()) throw Error(path, format_name + " without channels");
    return order;
}

}  // namespace leanfade::io::detail
