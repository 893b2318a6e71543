#include "shear/shear_progress.hpp"

namespace mrjam {

nlohmann::json CellProgress::to_json() const {
    nlohmann::json log = nlohmann::json::array();
    for (const MagnetiseCheck& c : magnetise_log)
        log.push_back(
            {{"time_s", c.time}, {"contacts_per_grain", c.contacts_per_grain}, {"mean_abs_cos", c.mean_abs_cos}});
    return {{"cell", cell},
            {"grains", grains},
            {"timestep_s", timestep},
            {"magnetise_log", log},
            {"magnetise_steps", magnetise_steps},
            {"settled", settled},
            {"magnetisation", magnetisation},
            {"rates", rates},
            {"samples", {{"upper", upper}, {"lower", lower}, {"bulk", bulk}}},
            {"max_overlap_ratio_seen", max_overlap}};
}

CellProgress CellProgress::from_json(const nlohmann::json& j) {
    CellProgress c;
    c.cell = j.at("cell").get<std::size_t>();
    c.grains = j.at("grains").get<std::size_t>();
    c.timestep = j.at("timestep_s").get<double>();
    for (const auto& e : j.at("magnetise_log"))
        c.magnetise_log.push_back({e.at("time_s").get<double>(), e.at("contacts_per_grain").get<double>(),
                                   e.at("mean_abs_cos").get<double>()});
    c.magnetise_steps = j.at("magnetise_steps").get<long>();
    c.settled = j.at("settled").get<bool>();
    c.magnetisation = j.at("magnetisation");
    c.rates = j.at("rates");
    c.upper = j.at("samples").at("upper").get<std::vector<double>>();
    c.lower = j.at("samples").at("lower").get<std::vector<double>>();
    c.bulk = j.at("samples").at("bulk").get<std::vector<double>>();
    c.max_overlap = j.at("max_overlap_ratio_seen").get<double>();
    return c;
}

nlohmann::json StudyProgress::to_json() const {
    return {{"cells", cells}, {"current", current ? current->to_json() : nlohmann::json(nullptr)}, {"engine", engine}};
}

StudyProgress StudyProgress::from_json(const nlohmann::json& j) {
    StudyProgress p;
    p.cells = j.at("cells");
    if (!j.at("current").is_null()) p.current = CellProgress::from_json(j.at("current"));
    p.engine = j.value("engine", nlohmann::json());
    return p;
}

}  // namespace mrjam
