#pragma once
// The magnetic dipoles as a force term: induced and permanent moments, pair forces and torques,
// the applied field's gradient force and the close-pair correction (lib/engine/magnetic/). The model's
// state stays in System::magnetic, where the neighbour rebuild keeps its pair list; this term
// adds its forces in the list's order and owns what a checkpoint must carry of it.
#include "force_term.hpp"

namespace mrjam {

class MagneticTerm final : public ForceTerm {
public:
    std::string name() const override { return "magnetic"; }
    std::unique_ptr<ForceTerm> clone() const override { return std::make_unique<MagneticTerm>(*this); }
    void add(System& s) override;
    void save(const System& s, std::ostream& out) const override;
    void load(System& s, std::istream& in) override;
    void grains_removed(System& s, const std::vector<std::int64_t>& index, std::size_t kept) override;
    void summarise(const System& s, nlohmann::json& summary) const override;
};

}  // namespace mrjam
