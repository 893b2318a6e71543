#pragma once
// Where a shear study stands, as the checkpoint carries it: the finished cells' records, and the
// cell in progress (its magnetisation checks, its finished rates, the samples of the rate under
// way). The step counts and the stage under way are the runner's (ProtocolPosition); the records
// of finished parts are report fragments, kept as the report will print them.
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

namespace mrjam {

struct MagnetiseCheck {
    double time = 0;  // s
    double contacts_per_grain = 0;
    double mean_abs_cos = 0;  // of contact normals to the field
};

struct CellProgress {
    std::size_t cell = 0;
    std::size_t grains = 0;
    double timestep = 0;  // s
    std::vector<MagnetiseCheck> magnetise_log;
    long magnetise_steps = 0;
    bool settled = false;
    nlohmann::json magnetisation;                    // the record, once the magnetisation ended
    nlohmann::json rates = nlohmann::json::array();  // a record per finished rate
    std::vector<double> upper, lower, bulk;          // Pa: stress samples of the rate under way
    double max_overlap = 0;                          // largest overlap ratio seen in this phase

    // The JSON the report's summary reads (cell, grains, timestep_s, magnetisation, rates) and
    // the checkpoint stores; from_json reads it back.
    nlohmann::json to_json() const;
    static CellProgress from_json(const nlohmann::json& j);
};

struct StudyProgress {
    nlohmann::json cells = nlohmann::json::array();  // finished cells' records
    std::optional<CellProgress> current;
    nlohmann::json engine;  // the first cell's engine scene and step, for the report

    nlohmann::json to_json() const;
    static StudyProgress from_json(const nlohmann::json& j);
};

}  // namespace mrjam
