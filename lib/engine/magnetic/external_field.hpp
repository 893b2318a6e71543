#pragma once
// The applied magnetic field B_ext(x, t) and its gradient. A uniform field exerts no force on a
// dipole; a real EPM valve's field does, through grad(m . B_ext) (eq. 4.6).
#include <array>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace mrjam {

// 3x3 matrix, row-major: gradient[l][k] = d B_l / d x_k.
using Gradient = std::array<std::array<double, 3>, 3>;

class ExternalField {
public:
    virtual ~ExternalField() = default;
    virtual Vec3 flux_density(const Vec3& x, double time) const = 0;  // tesla
    virtual Gradient gradient(const Vec3& x, double time) const = 0;  // tesla per metre
    virtual bool uniform() const = 0;  // true: no gradient anywhere, the force term is skipped
    virtual std::string name() const = 0;
    // True when the field is zero everywhere at `time` (a magnet switched off): grains without a
    // permanent moment then carry none, and the magnetic pass is skipped.
    virtual bool off_at(double /*time*/) const { return false; }
};

// B = B0 s(t): s = 0 before `switch_on`, rising linearly to 1 over `ramp` (0: a step), and back
// to 0 after `switch_off` (infinite by default).
class UniformField final : public ExternalField {
public:
    UniformField(Vec3 b0, double switch_on, double ramp, double switch_off)
        : b0_(b0), on_(switch_on), ramp_(ramp), off_(switch_off) {}
    Vec3 flux_density(const Vec3&, double time) const override { return b0_ * strength(time); }
    Gradient gradient(const Vec3&, double) const override { return {}; }
    bool uniform() const override { return true; }
    std::string name() const override { return "uniform"; }
    bool off_at(double time) const override { return strength(time) == 0.0 || norm2(b0_) == 0.0; }
    double strength(double time) const;

private:
    Vec3 b0_;
    double on_, ramp_, off_;
};

// B sampled on a regular grid (x fastest), trilinear between nodes. The gradient is the exact
// derivative of the trilinear interpolant. Outside the grid the field is clamped to the nearest
// face value and its gradient taken as zero across that face.
//
// File format (text, written by `mrjam magnetics --field-map`):
//   mrjam-fieldmap 1
//   nx ny nz
//   x0 y0 z0            origin (first node), metres
//   dx dy dz            node spacing, metres
//   Bx By Bz            nx*ny*nz lines, tesla, x fastest then y then z
class FieldMap final : public ExternalField {
public:
    FieldMap(std::array<int, 3> count, Vec3 origin, Vec3 spacing, std::vector<Vec3> values, double scale = 1.0);
    static FieldMap read(const std::string& path, double scale = 1.0);  // throws with the line number
    void write(const std::string& path) const;

    Vec3 flux_density(const Vec3& x, double time) const override;
    Gradient gradient(const Vec3& x, double time) const override;
    bool uniform() const override { return false; }
    std::string name() const override { return "map"; }
    Vec3 lower_corner() const { return origin_; }
    Vec3 upper_corner() const;
    double largest_flux_density() const;  // T, the strongest node, scale included

private:
    struct Cell {
        int i[3];
        double f[3];
        bool outside[3];
    };
    Cell locate(const Vec3& x) const;
    const Vec3& node(int i, int j, int k) const {
        return values_[(static_cast<std::size_t>(k) * count_[1] + j) * count_[0] + i];
    }

    std::array<int, 3> count_;
    Vec3 origin_, spacing_;
    std::vector<Vec3> values_;
    double scale_;
};

// Another field switched on and off at times a mode decides while running (the jam predictor
// switches the magnet off when the flow has arrested). Zero before `on` and from `off` on.
class SwitchedField final : public ExternalField {
public:
    explicit SwitchedField(std::shared_ptr<ExternalField> inner, double on = 0.0,
                           double off = std::numeric_limits<double>::infinity())
        : inner_(std::move(inner)), on_(on), off_(off) {}
    Vec3 flux_density(const Vec3& x, double time) const override {
        return active(time) ? inner_->flux_density(x, time) : Vec3{};
    }
    Gradient gradient(const Vec3& x, double time) const override {
        return active(time) ? inner_->gradient(x, time) : Gradient{};
    }
    bool uniform() const override { return inner_->uniform(); }
    std::string name() const override { return inner_->name(); }
    bool off_at(double time) const override { return !active(time) || inner_->off_at(time); }
    void switch_off_at(double time) { off_ = time; }
    double switch_off_time() const { return off_; }  // infinity until switched off
    bool active(double time) const { return time >= on_ && time < off_; }

private:
    std::shared_ptr<ExternalField> inner_;
    double on_, off_;
};

}  // namespace mrjam
