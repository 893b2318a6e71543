#include "force_term.hpp"

#include "core/binary_io.hpp"

namespace mrjam {

void HoldSchedule::save(std::ostream& out) const {
    binary::put(out, age);
    binary::put(out, reused);
}

void HoldSchedule::load(std::istream& in) {
    age = binary::get<int>(in);
    reused = binary::get<long>(in);
}

ForceTerms::ForceTerms(const ForceTerms& other) {
    for (const auto& t : other.terms_) terms_.push_back(t->clone());
    sort_by_kind();
}

ForceTerms& ForceTerms::operator=(const ForceTerms& other) {
    if (this != &other) {
        ForceTerms copy(other);
        *this = std::move(copy);
    }
    return *this;
}

ForceTerm& ForceTerms::add(std::unique_ptr<ForceTerm> term) {
    terms_.push_back(std::move(term));
    sort_by_kind();
    return *terms_.back();
}

void ForceTerms::sort_by_kind() {
    per_grain_.clear();
    whole_system_.clear();
    for (const auto& t : terms_) (t->per_grain() ? per_grain_ : whole_system_).push_back(t.get());
}

}  // namespace mrjam
