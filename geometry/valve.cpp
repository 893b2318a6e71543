#include "geometry/valve.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace mrjam {

double ValveGeometry::passage_radius(double z) const {
    const double start = taper_start_z();
    const double throat_start = -0.5 * throat_length;
    if (z < start || z > throat_end_z()) return bore_radius();
    if (z >= throat_start) return throat_radius();
    const double t = (z - start) / taper_length;  // 0 at the bore, 1 at the throat
    return bore_radius() + t * (throat_radius() - bore_radius());
}

SlotOrifice ValveGeometry::slot() const {
    return SlotOrifice{bore_radius(),   0.5 * slot_width,     throat_radius(),
                       taper_start_z(), -0.5 * throat_length, throat_end_z()};
}

double ValveGeometry::passage_half_height(double z) const {
    if (!is_slot()) return passage_radius(z);
    return std::min(slot().half_y(z), bore_radius());
}

double ValveGeometry::section_area(double z) const {
    if (is_slot()) return slot().section_area(z);
    const double r = passage_radius(z);
    return std::numbers::pi * r * r;
}

bool ValveGeometry::in_fluid(const Vec3& p) const {
    if (p.z < -upstream_length || p.z > downstream_length) return false;
    if (is_slot()) return slot().contains(p);
    const double r = passage_radius(p.z);
    return p.x * p.x + p.y * p.y < r * r;
}

double ValveGeometry::fluid_volume() const {
    const double pi = std::numbers::pi;
    const double rb = bore_radius(), rt = throat_radius();
    const double bore = pi * rb * rb * (upstream_length + downstream_length - taper_length - throat_length);
    if (is_slot()) return bore + slot().constriction_volume();
    const double cone = pi * taper_length * (rb * rb + rb * rt + rt * rt) / 3.0;
    const double throat = pi * rt * rt * throat_length;
    return bore + cone + throat;
}

std::vector<std::string> ValveGeometry::problems() const {
    std::vector<std::string> out;
    auto say = [&out](const std::string& field, const std::string& what) { out.push_back(field + ": " + what); };
    auto mm = [](double v) {
        std::ostringstream s;
        s << v * 1e3 << " mm";
        return s.str();
    };
    if (!(tube_inner_diameter > 0)) say("tube_inner_diameter", "must be positive");
    if (!(wall_thickness > 0)) say("wall_thickness", "must be positive (the valve body needs a wall)");
    if (!(constriction_diameter > 0)) say("constriction_diameter", "must be positive");
    if (!(taper_length >= 0)) say("taper_length", "must not be negative");
    if (!(throat_length >= 0)) say("throat_length", "must not be negative");
    if (taper_length == 0 && throat_length == 0)
        say("throat_length", "taper_length and throat_length are both zero: give the constriction some length");
    if (is_slot()) {
        if (!(slot_width > 0))
            say("slot_width", "a slot orifice needs its width across the field (x), e.g. \"0.6 mm\"");
        else if (std::hypot(slot_width, constriction_diameter) >= tube_inner_diameter)
            say("slot_width",
                "the slot " + mm(slot_width) + " x " + mm(constriction_diameter) + " does not fit inside the bore " +
                    mm(tube_inner_diameter) + " (its diagonal " + mm(std::hypot(slot_width, constriction_diameter)) +
                    " must be shorter than the bore); narrow the slot or its height (constriction_diameter)");
    } else if (slot_width != 0) {
        say("slot_width", "is for a slot orifice; set \"orifice\": \"slot\" or drop slot_width");
    }
    if (constriction_diameter >= tube_inner_diameter)
        say("constriction_diameter", mm(constriction_diameter) + " is not narrower than the tube bore " +
                                         mm(tube_inner_diameter) + "; make it smaller than the bore");
    if (!(upstream_length > -taper_start_z()))
        say("upstream_length",
            "must reach beyond the taper start (" + mm(-taper_start_z()) + " upstream of the throat centre)");
    if (!(downstream_length > throat_end_z()))
        say("downstream_length",
            "must reach beyond the throat exit (" + mm(throat_end_z()) + " downstream of the throat centre)");
    return out;
}

double constriction_preset(const std::string& name) {
    if (name == "20x") return 0.88e-3;
    if (name == "30x") return 1.32e-3;
    if (name == "40x") return 1.76e-3;
    return 0.0;
}

std::vector<std::string> constriction_preset_names() { return {"20x", "30x", "40x"}; }

}  // namespace mrjam
