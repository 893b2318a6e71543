#pragma once
// The design's one-look summary figure (summary.svg and its PNG twin in the design's output
// directory): the jam probability over the seeds (95 % Wilson interval) and the open valve's flow
// against the throat diameter, beside the mid-plane |B| picture of the chosen constriction.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "design/design_scenes.hpp"

namespace mrjam {

struct DesignSummary {
    std::string svg_path;  // "" when nothing was drawn (no constriction finished)
    std::string png_path;
    std::string field_of;  // the constriction whose field is shown ("" when none has a picture)
};

// `rows` are the finished constrictions' rows in the design's order (each with diameter_m,
// jam_probability, jam_probability_95ci, open_flow_rate_ml_min and, when drawn, field_picture);
// `widest` the widest that jams reliably ("" for none). The field shown is the widest's, or
// without one the constriction most likely to jam (the narrowest of equals).
DesignSummary write_design_summary(const nlohmann::json& rows, const std::string& widest,
                                   const std::filesystem::path& svg_path);

}  // namespace mrjam
