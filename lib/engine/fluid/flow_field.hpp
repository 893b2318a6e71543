#pragma once
// Background carrier-fluid velocity for Stokes drag (one-way coupled: the grains feel the fluid,
// the fluid does not feel the grains). Called once per grain per step, so a virtual call is fine.
#include <memory>
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace mrjam {

class FlowField {
public:
    virtual ~FlowField() = default;
    virtual Vec3 velocity(const Vec3& x, double time) const = 0;
    virtual std::string name() const = 0;
    // Multiplies the Stokes drag at x: 1 for a dilute suspension; a hindered-drag model (the
    // valve's packed-bed resistance) raises it where grains pack.
    virtual double drag_factor(const Vec3&) const { return 1.0; }
    // Both at once, for the drag pass: a flow that locates x on a grid for both (the coupled
    // valve flow's slice and ring) overrides it to locate x once.
    struct Drag {
        Vec3 velocity;
        double factor;
    };
    virtual Drag drag_at(const Vec3& x, double time) const { return {velocity(x, time), drag_factor(x)}; }
};

class StillFlow final : public FlowField {
public:
    Vec3 velocity(const Vec3&, double) const override { return {}; }
    std::string name() const override { return "still"; }
};

class UniformFlow final : public FlowField {
public:
    explicit UniformFlow(Vec3 u) : u_(u) {}
    Vec3 velocity(const Vec3&, double) const override { return u_; }
    std::string name() const override { return "uniform"; }

private:
    Vec3 u_;
};

// Linear profile between two walls normal to `gradient_axis`: velocity `lower_velocity` at
// coordinate `lower`, `upper_velocity` at `upper`, constant beyond them (fig. 2.4).
class CouetteFlow final : public FlowField {
public:
    CouetteFlow(int gradient_axis, double lower, double upper, Vec3 lower_velocity, Vec3 upper_velocity)
        : axis_(gradient_axis), lower_(lower), upper_(upper), v_lower_(lower_velocity), v_upper_(upper_velocity) {}
    Vec3 velocity(const Vec3& x, double) const override {
        double s = (x[axis_] - lower_) / (upper_ - lower_);
        s = s < 0 ? 0 : (s > 1 ? 1 : s);
        return v_lower_ + (v_upper_ - v_lower_) * s;
    }
    std::string name() const override { return "couette"; }
    double shear_rate() const { return norm(v_upper_ - v_lower_) / (upper_ - lower_); }

private:
    int axis_;
    double lower_, upper_;
    Vec3 v_lower_, v_upper_;
};

// The affine simple shear of a Lees-Edwards cell: u = rate (x[gradient] - centre) along `flow_axis`,
// unbounded, so a grain that has crossed the sliding boundary but is not yet wrapped still sees
// the flow its images see (u jumps by rate L exactly where the wrap changes its velocity by as much).
class SimpleShearFlow final : public FlowField {
public:
    SimpleShearFlow(int flow_axis, int gradient_axis, double rate, double centre)
        : flow_(flow_axis), gradient_(gradient_axis), rate_(rate), centre_(centre) {}
    Vec3 velocity(const Vec3& x, double) const override {
        Vec3 u{};
        u[flow_] = rate_ * (x[gradient_] - centre_);
        return u;
    }
    std::string name() const override { return "simple_shear"; }
    double shear_rate() const { return rate_; }

private:
    int flow_, gradient_;
    double rate_, centre_;
};

// Flow along a tube axis: centreline speed u(s) tabulated along the axis coordinate s (linear
// interpolation, constant beyond the ends; one point gives a constant), with a parabolic
// (Poiseuille) or plug shape across a radius that may also vary with s. Zero outside the tube.
class AxialFlow final : public FlowField {
public:
    struct Station {
        double position;          // along the axis, m
        double centreline_speed;  // m/s
        double radius;            // tube radius at this station, m
    };
    AxialFlow(int axis, Vec3 centre, std::vector<Station> stations, bool parabolic);
    Vec3 velocity(const Vec3& x, double) const override;
    std::string name() const override { return "axial"; }

private:
    int axis_;
    Vec3 centre_;
    std::vector<Station> stations_;
    bool parabolic_;
};

}  // namespace mrjam
