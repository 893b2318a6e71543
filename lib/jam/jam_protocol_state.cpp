#include "jam/jam_protocol_state.hpp"

namespace mrjam {

nlohmann::json JamProtocolState::save() const {
    nlohmann::json history = nlohmann::json::array();
    for (const auto& f : flow_history) history.push_back({f.time, f.scale, f.stretch_pressure, f.max_fraction});
    nlohmann::json settle = nlohmann::json::array();
    for (const auto& x : settle_history) settle.push_back({x.time, x.coordination, x.magnetic_energy});
    return {{"flux", flux.save()},
            {"base_rate", base_rate},
            {"arrest_time", arrest_time},
            {"release_start", release_start},
            {"judged_from", judged_from},
            {"settle_history", settle},
            {"settled", settled},
            {"magnetise_end", magnetise_end},
            {"passed_at_switch_on", passed_at_switch_on},
            {"passed_at_arrest", passed_at_arrest},
            {"jammed", jammed},
            {"released", released},
            {"undetermined", undetermined},
            {"reference_expected", reference_expected},
            {"steady", steady},
            {"batch", {drained, upstream_at_start, upstream_at_arrest, upstream_now}},
            {"flow_scale", flow_state.scale},
            {"flow_state",
             {flow_state.arrested_pressure, flow_state.stretch_pressure, flow_state.max_fraction,
              flow_state.max_drag_factor}},
            {"flow_history", history},
            {"arrest_clusters", {arrest_view.valid, arrest_view.largest, arrest_view.count, arrest_view.spans}}};
}

void JamProtocolState::restore(const nlohmann::json& st) {
    flux.restore(st.at("flux"));
    base_rate = st.at("base_rate");
    arrest_time = st.at("arrest_time");
    release_start = st.at("release_start");
    judged_from = st.at("judged_from");
    settled = st.at("settled");
    magnetise_end = st.at("magnetise_end");
    settle_history.clear();
    for (const auto& row : st.at("settle_history"))
        settle_history.push_back({row.at(0).get<double>(), row.at(1).get<double>(), row.at(2).get<double>()});
    passed_at_switch_on = st.at("passed_at_switch_on");
    passed_at_arrest = st.at("passed_at_arrest");
    jammed = st.at("jammed");
    released = st.at("released");
    undetermined = st.at("undetermined");
    reference_expected = st.at("reference_expected");
    steady = st.value("steady", false);
    if (st.contains("batch")) {  // checkpoints written before model/supply have none
        const auto b = st.at("batch").get<std::vector<long>>();
        drained = b.at(0);
        upstream_at_start = b.at(1);
        upstream_at_arrest = b.at(2);
        upstream_now = b.at(3);
    }
    const auto fs = st.at("flow_state").get<std::vector<double>>();
    flow_state.scale = st.at("flow_scale").get<double>();
    flow_state.arrested_pressure = fs.at(0);
    flow_state.stretch_pressure = fs.at(1);
    flow_state.max_fraction = fs.at(2);
    flow_state.max_drag_factor = fs.at(3);
    flow_history.clear();
    for (const auto& row : st.at("flow_history"))
        flow_history.push_back(
            {row.at(0).get<double>(), row.at(1).get<double>(), row.at(2).get<double>(), row.at(3).get<double>()});
    const auto& ac = st.at("arrest_clusters");
    arrest_view = {ac.at(1).get<long>(), ac.at(2).get<long>(), ac.at(3).get<bool>(), ac.at(0).get<bool>()};
}

}  // namespace mrjam
