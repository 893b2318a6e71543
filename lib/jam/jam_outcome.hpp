#pragma once
// A jam run's verdict in Table 3.2's words. The experiment closed the valve, applied the supply
// pressure with the magnet on and then opened it: "Fail-No Jam" when the fluid got through with
// the magnet on, "Fail-Irreversible" when it did not get through after the magnet was switched
// off, "Success" otherwise. The model sees an arrest of the grain flux; when the protocol holds
// the field on after it (protocol/hold_time), an arrest that breaks under the held field is what
// the experiment would have seen as a valve that does not jam, so it is its own failure,
// "fail-no-hold", and it does not count towards the jam probability.
#include <string>

namespace mrjam {

struct JamVerdict {
    bool undetermined = false;  // no grain crossed the throat without field, and few would have
    bool clogged = false;       // no grain crossed the throat without field, though many would have
    bool field_free = false;    // the scene applies no field: an arrest is a plain clog
    bool incomplete = false;    // the run stopped (interrupted, blew up) before its protocol ended
    bool blew_up = false;       // ... because it blew up: no resume will finish it as it stands
    bool jammed = false;        // the grain flux arrested with the field on
    bool hold_asked = false;    // protocol/hold_time > 0
    bool held = false;          // ... and the flux stayed below arrest_fraction over it
    bool released = false;      // the flux came back with the field off
};

// "success", "fail-no-jam", "fail-no-hold", "fail-irreversible", "clog" (the throat clogs with no
// field: in the no-field reference flow, or in a scene without a field), or why there is none yet.
std::string jam_outcome_word(const JamVerdict& v);

// Did the valve stop the grains (and, with a hold, keep them stopped)? What the jam probability counts.
bool jam_stops_flow(const JamVerdict& v);

}  // namespace mrjam
