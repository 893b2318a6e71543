#pragma once
// The force terms a scene switches on, as a list the force pass walks (HOOMD-blue's force
// computes; LAMMPS's pair styles and fixes that add forces). The contact law is not in the list:
// it is the pass itself, a templated pair loop (lib/engine/forces.cpp) with no virtual call per pair.
// Every other piece of physics is a ForceTerm that owns its settings, its held values and its
// checkpoint state, so a new term is one class and one line where the scene builds it
// (docs/engine.md walks through one).
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace mrjam {

struct System;

// "Evaluate every k steps and hold" (multiple time stepping), written once: a term whose values
// change slowly next to the contact step evaluates them every `interval` steps and reuses them
// in between. The term keeps the values; this keeps the count.
struct HoldSchedule {
    int interval = 1;  // steps between evaluations; 1: every step
    int age = 0;       // steps (the evaluating one included) that have used the held values
    long reused = 0;   // steps so far that reused held values

    // Whether this step may reuse values held for `held_for` grains among `grains` now (a removal
    // or a cleared hold forces a fresh evaluation).
    bool reuse_now(std::size_t held_for, std::size_t grains) const {
        return interval > 1 && held_for == grains && held_for > 0 && age < interval;
    }
    bool holding() const { return interval > 1; }
    void reused_once() {
        ++age;
        ++reused;
    }
    void evaluated() { age = 1; }
    void save(std::ostream& out) const;
    void load(std::istream& in);
};

class ForceTerm {
public:
    virtual ~ForceTerm() = default;
    // The term's name, as the report and the checkpoint write it.
    virtual std::string name() const = 0;
    // A copy with the same settings and state (a System copies its terms).
    virtual std::unique_ptr<ForceTerm> clone() const = 0;

    // A per-grain term (drag, gravity) runs inside the contact pass's threads over each thread's
    // own grains, adding to the thread's force buffer: no pass over memory of its own.
    // begin_pass and end_pass run on the calling thread around that pass.
    virtual bool per_grain() const { return false; }
    virtual void begin_pass(const System&) {}
    virtual void add_per_grain(const System&, Vec3* force, std::size_t begin, std::size_t end) {
        (void)force, (void)begin, (void)end;
    }
    virtual void end_pass() {}

    // A whole-system term (magnetic dipoles, pair damping) runs after the contact pass, in list
    // order, adding to the grains' force and torque arrays (and to rafts' forces it acts on).
    virtual void add(System&) {}

    // Checkpoint state: what the term carries from one step to the next beyond the grains
    // (held values, pair lists, counters). Written in list order, each under its name.
    virtual void save(const System&, std::ostream&) const {}
    virtual void load(System&, std::istream&) {}

    // Grains were taken out: `index[i]` is grain i's new index (-1: removed), `kept` remain.
    virtual void grains_removed(System&, const std::vector<std::int64_t>& index, std::size_t kept) {
        (void)index, (void)kept;
    }

    // The term's part of a report's state summary (counts, held steps), under its name.
    virtual void summarise(const System&, nlohmann::json&) const {}
};

// The terms in the order they add their forces (the order fixes the floating-point sums, so a
// scene's trajectory does not depend on anything but the scene).
class ForceTerms {
public:
    ForceTerms() = default;
    ForceTerms(const ForceTerms& other);
    ForceTerms& operator=(const ForceTerms& other);
    ForceTerms(ForceTerms&&) = default;
    ForceTerms& operator=(ForceTerms&&) = default;

    ForceTerm& add(std::unique_ptr<ForceTerm> term);

    template <class T>
    T* find() {
        for (auto& t : terms_)
            if (auto* p = dynamic_cast<T*>(t.get())) return p;
        return nullptr;
    }
    template <class T>
    const T* find() const {
        for (const auto& t : terms_)
            if (const auto* p = dynamic_cast<const T*>(t.get())) return p;
        return nullptr;
    }

    auto begin() { return terms_.begin(); }
    auto end() { return terms_.end(); }
    auto begin() const { return terms_.begin(); }
    auto end() const { return terms_.end(); }
    std::size_t size() const { return terms_.size(); }
    // The per-grain and the whole-system terms, each in list order (kept as the list changes,
    // so the force pass allocates nothing).
    const std::vector<ForceTerm*>& per_grain_terms() const { return per_grain_; }
    const std::vector<ForceTerm*>& whole_system_terms() const { return whole_system_; }

private:
    void sort_by_kind();
    std::vector<std::unique_ptr<ForceTerm>> terms_;
    std::vector<ForceTerm*> per_grain_, whole_system_;
};

}  // namespace mrjam
