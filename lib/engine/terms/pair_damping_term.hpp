#pragma once
// Pairwise contact damping f_i = -c (v_i - v_j) between touching grains (c in N s/m): a
// dissipation that, unlike drag against a background flow, does not impose the affine velocity
// profile (Lees-Edwards-free DEM rheology uses it; the shear mode offers it). It reads the
// contact list's touching flags, which the contact pass has just set.
#include "force_term.hpp"

namespace mrjam {

class PairDampingTerm final : public ForceTerm {
public:
    explicit PairDampingTerm(double coefficient) : coefficient_(coefficient) {}

    std::string name() const override { return "pair_damping"; }
    std::unique_ptr<ForceTerm> clone() const override { return std::make_unique<PairDampingTerm>(*this); }
    void add(System& s) override;

    double coefficient() const { return coefficient_; }

private:
    double coefficient_;
};

// The pair damping coefficient of a system (N s/m); 0 without the term.
double pair_damping_coefficient(const System& s);

}  // namespace mrjam
