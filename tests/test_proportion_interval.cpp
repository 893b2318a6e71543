// The Wilson score interval that goes with every jam probability from N seeds.
#include <doctest/doctest.h>

#include <cmath>
#include <initializer_list>

#include "core/proportion_interval.hpp"

using namespace mrjam;

TEST_SUITE("unit") {
    TEST_CASE("wilson interval: its bounds solve the score equation, and it stays in [0, 1]") {
        const double z = kZ95;
        for (int n = 1; n <= 12; ++n)
            for (int k = 0; k <= n; ++k) {
                CAPTURE(n);
                CAPTURE(k);
                const ProportionInterval ci = wilson_interval(k, n);
                const double p = static_cast<double>(k) / n;
                CHECK(ci.low >= 0);
                CHECK(ci.high <= 1);
                CHECK(ci.low <= p);
                CHECK(ci.high >= p);
                // Each bound is a root of (p - b)^2 = z^2 b (1 - b) / n.
                for (const double b : {ci.low, ci.high})
                    CHECK(std::abs((p - b) * (p - b) - z * z * b * (1 - b) / n) < 1e-12);
                // k of n jams and n - k of n mirror each other.
                const ProportionInterval mirror = wilson_interval(n - k, n);
                CHECK(std::abs(ci.low - (1 - mirror.high)) < 1e-12);
                CHECK(std::abs(ci.high - (1 - mirror.low)) < 1e-12);
                // More seeds with the same share: a narrower interval.
                const ProportionInterval more = wilson_interval(4 * k, 4 * n);
                CHECK(more.high - more.low < ci.high - ci.low);
            }
    }

    TEST_CASE("wilson interval: none or all of n has the closed form z^2 / (n + z^2); no seeds say nothing") {
        const double z2 = kZ95 * kZ95;
        for (const int n : {1, 3, 8, 30}) {
            CAPTURE(n);
            CHECK(wilson_interval(0, n).low == 0.0);
            CHECK(std::abs(wilson_interval(0, n).high - z2 / (n + z2)) < 1e-12);
            CHECK(wilson_interval(n, n).high == 1.0);
            CHECK(std::abs(wilson_interval(n, n).low - n / (n + z2)) < 1e-12);
        }
        CHECK(wilson_interval(0, 0).low == 0.0);
        CHECK(wilson_interval(0, 0).high == 1.0);
    }

}  // TEST_SUITE
