// libFuzzer target for the scene readers and the unit parser (issue #43): any input is either
// accepted or refused with a SceneError / UnitError; any other exception, a crash, a hang or a
// sanitizer report is a finding. Built and run by scripts/fuzz.sh (clang, -fsanitize=fuzzer,
// address, undefined), outside CI's budget; its seed corpus is tests/fuzz/corpus/.
//
// The first byte chooses the reader, the rest is the input: a unit string, or a JSON scene for
// the jam, shear, asteroid or `run` reader (`run` as a resumed scene reads it: every block checked,
// no grains packed, since a packing's cost is the grain count the memory estimate bounds).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>

#include "asteroid/scaling_spec.hpp"
#include "jam/jam_scene.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "scene/units.hpp"
#include "shear/shear_spec.hpp"

namespace {

void read_as(std::uint8_t which, const std::string& text) {
    if (which % 5 == 0) {
        (void)mrjam::units::parse(text);
        return;
    }
    // Depth-limited as the CLI reads files (apps/cli_common: 64 levels).
    int depth = 0;
    const auto limit = [&depth](int, nlohmann::json::parse_event_t event, nlohmann::json&) {
        if (event == nlohmann::json::parse_event_t::object_start || event == nlohmann::json::parse_event_t::array_start)
            ++depth;
        if (event == nlohmann::json::parse_event_t::object_end || event == nlohmann::json::parse_event_t::array_end)
            --depth;
        return depth <= 64;
    };
    const nlohmann::json scene = nlohmann::json::parse(text, limit, false);
    if (scene.is_discarded()) return;
    if (which % 5 == 1) (void)mrjam::read_jam_scene(scene, "quick", ".");
    if (which % 5 == 2) (void)mrjam::read_shear_spec(scene, "quick");
    if (which % 5 == 3) (void)mrjam::read_scaling_spec(scene);
    if (which % 5 == 4) {
        mrjam::BuildOptions read_only;
        read_only.insert_grains = false;
        read_only.fidelity = "quick";
        (void)mrjam::build_scene(scene, read_only);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
    try {
        read_as(data[0], text);
    } catch (const mrjam::SceneError&) {
    } catch (const mrjam::units::UnitError&) {
    } catch (const std::exception& e) {
        // Not a refusal: a finding. abort() makes libFuzzer save the input.
        std::fprintf(stderr, "not a SceneError or UnitError: %s\n", e.what());
        std::abort();
    }
    return 0;
}
