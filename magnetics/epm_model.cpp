#include "magnetics/epm_model.hpp"

#include <sstream>
#include <stdexcept>

namespace mrjam::magnetics {

std::string variant_name(BracketVariant v) {
    switch (v) {
        case BracketVariant::unguided:
            return "unguided";
        case BracketVariant::rectangular:
            return "rectangular";
        case BracketVariant::curved:
            return "curved";
        case BracketVariant::unchamfered:
            return "unchamfered";
        case BracketVariant::insert:
            return "insert";
    }
    return "?";
}

std::vector<std::string> variant_names() { return {"unguided", "rectangular", "curved", "unchamfered", "insert"}; }

BracketVariant variant_from_name(const std::string& name) {
    for (auto v : {BracketVariant::unguided, BracketVariant::rectangular, BracketVariant::curved,
                   BracketVariant::unchamfered, BracketVariant::insert})
        if (variant_name(v) == name) return v;
    throw std::invalid_argument("unknown bracket variant '" + name + "'");
}

double EpmModel::bracket_tip_x() const {
    return bracket.variant == BracketVariant::unguided ? magnet_front_x() : bracket.tip_reach;
}

std::vector<std::string> EpmModel::problems() const {
    std::vector<std::string> out;
    for (const auto& p : valve.problems()) out.push_back("/valve/" + p);
    auto say = [&out](const std::string& path, const std::string& what) { out.push_back(path + ": " + what); };
    // The field model's fluid volume and the circuit estimate are built from a circular
    // constriction; a slot would be modelled as a circle without a word, so it is refused.
    if (valve.is_slot())
        say("/valve/orifice",
            "magnetics models circular orifices only; use \"circular\" here (a slot valve can be run by "
            "`mrjam jam` in a uniform field or a field map solved for the circular valve)");
    auto mm = [](double v) {
        std::ostringstream s;
        s << v * 1e3 << " mm";
        return s.str();
    };
    const auto& m = magnets;
    if (!(m.width > 0)) say("/magnets/width", "must be positive");
    if (!(m.depth > 0)) say("/magnets/depth", "must be positive");
    if (!(m.length > 0)) say("/magnets/length", "must be positive");
    if (!(m.spacing >= 0)) say("/magnets/spacing", "must not be negative");
    for (const auto& [name, mat] : {std::pair{"ndfeb", m.ndfeb}, std::pair{"alnico", m.alnico}}) {
        if (!(mat.remanence >= 0)) say(std::string("/magnets/") + name + "/remanence", "must not be negative");
        if (!(mat.recoil_permeability >= 1))
            say(std::string("/magnets/") + name + "/recoil_permeability", "must be at least 1");
    }
    const auto& b = bracket;
    if (!(b.thickness > 0))
        say("/bracket/thickness", "must be positive (a bracket thinner than zero cannot carry flux)");
    if (!(b.tube_clearance >= 0))
        say("/bracket/tube_clearance", "must not be negative (the magnets would cut into the tube)");
    if (!(b.width > 0))
        say("/bracket/width", "must be positive");
    else if (b.width < magnets_z_span())
        say("/bracket/width", mm(b.width) + " is narrower than the two magnets side by side (" + mm(magnets_z_span()) +
                                  "): the magnets do not fit the caps; widen the caps or shrink the magnets");
    if (valve.outer_diameter() > gap() + 1e-12)
        say("/valve/wall_thickness", "the valve body (outer diameter " + mm(valve.outer_diameter()) +
                                         ") does not fit between the brackets (gap = magnet length " + mm(gap()) +
                                         "); thin the wall, narrow the bore or lengthen the magnets");
    // The modelled tube must run out from under the brackets on both sides: the body's end faces
    // cannot meet the brackets' faces (gmsh's boolean cut fails there), and the field map needs
    // the fluid beyond the brackets where the field falls off. 0.25 mm past the caps is the least
    // the 3D mesh was tried with.
    for (const auto& [path, length] : {std::pair{"/valve/upstream_length", valve.upstream_length},
                                       std::pair{"/valve/downstream_length", valve.downstream_length}})
        if (b.width > 0 && length < 0.5 * b.width + 0.25e-3)
            say(path, mm(length) + " ends under the brackets (half their width is " + mm(0.5 * b.width) +
                          "); model at least " + mm(0.5 * b.width + 0.25e-3) + " of tube on each side of the throat");
    if (b.variant != BracketVariant::unguided) {
        const double r = 0.5 * valve.outer_diameter();
        if (b.tip_reach < -r)
            say("/bracket/tip_reach",
                "the tips stop short of the tube (tip_reach < -outer radius); reach at least to the tube wall");
        if (b.tip_reach > r)
            say("/bracket/tip_reach",
                "the tips overshoot the tube by more than its radius; at most the outer radius " + mm(r));
        if (!(b.chamfer >= 0) || b.chamfer >= b.thickness)
            say("/bracket/chamfer", "must lie in [0, bracket thickness)");
        if (b.variant == BracketVariant::curved) {
            // The cutout is a half-disc notch in the inner face, starting at the magnets' front face.
            if (!(b.cutout_radius > 0) || b.cutout_radius >= b.thickness)
                say("/bracket/cutout_radius", "must lie in (0, bracket thickness)");
            else if (magnet_front_x() + 2.0 * b.cutout_radius > bracket_tip_x() - b.chamfer)
                say("/bracket/cutout_radius", "the cutout reaches past the bracket tip; make it smaller than " +
                                                  mm(0.5 * (bracket_tip_x() - b.chamfer - magnet_front_x())));
        }
        if (b.variant == BracketVariant::insert) {
            if (!(b.insert_width > 0)) say("/bracket/insert_width", "must be positive");
            if (b.insert_width > valve.tube_inner_diameter)
                say("/bracket/insert_width",
                    "inserts wider than the bore would cut through the whole valve body; at most " +
                        mm(valve.tube_inner_diameter));
        }
    }
    if (!(materials.iron_relative_permeability >= 1))
        say("/materials/iron_relative_permeability", "must be at least 1");
    if (!(materials.fluid_relative_permeability >= 1))
        say("/materials/fluid_relative_permeability", "must be at least 1");
    if (!(materials.iron_saturation > 0)) say("/materials/iron_saturation", "must be positive");
    return out;
}

}  // namespace mrjam::magnetics
