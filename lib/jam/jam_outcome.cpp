#include "jam/jam_outcome.hpp"

namespace mrjam {

bool jam_stops_flow(const JamVerdict& v) {
    if (v.clogged) return !v.incomplete && !v.blew_up;  // clogged in the reference flow
    return v.jammed && (!v.hold_asked || v.held);
}

std::string jam_outcome_word(const JamVerdict& v) {
    if (v.undetermined) return "undetermined";
    // A run stopped before its protocol ended has no outcome yet: only an arrest is already known.
    if (v.blew_up) return "failed (the run blew up: the report's error says where, and what to change)";
    if (v.incomplete)
        return v.jammed ? "incomplete (arrested; release not yet tested)"
                        : "incomplete (no arrest yet; resume with mrjam jam --resume)";
    if (v.clogged) return "clog";
    if (!v.jammed) return "fail-no-jam";
    if (v.field_free) return v.hold_asked && !v.held ? "fail-no-hold" : "clog";
    if (v.hold_asked && !v.held) return "fail-no-hold";
    return v.released ? "success" : "fail-irreversible";
}

}  // namespace mrjam
