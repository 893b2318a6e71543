// Libraries opened at run time (core/shared_library.hpp): a function comes back callable, and a
// library or function that is not there is an error naming it and the fix, never a null call.
#include <doctest/doctest.h>

#include <stdexcept>
#include <string>

#include "core/shared_library.hpp"

TEST_SUITE("unit") {
    TEST_CASE("shared library: a function resolves and runs; a missing library or function names itself") {
        const auto libm = mrjam::SharedLibrary::open<std::runtime_error>("libm.so.6", "libm.so.6", "install libc");
        double (*cosine)(double) = nullptr;
        libm.resolve<std::runtime_error>(cosine, "cos", "install libc");
        REQUIRE(static_cast<bool>(cosine));
        CHECK(cosine(0.0) == 1.0);
        try {
            double (*missing)(double) = nullptr;
            libm.resolve<std::runtime_error>(missing, "mrjam_no_such_function", "use another libm");
            FAIL("a missing function resolved");
        } catch (const std::runtime_error& e) {
            const std::string what = e.what();
            CHECK(what.find("mrjam_no_such_function") != std::string::npos);
            CHECK(what.find("use another libm") != std::string::npos);
        }
        try {
            (void)mrjam::SharedLibrary::open<std::runtime_error>("libmrjam_absent.so.9",
                                                                 "/nonexistent/libmrjam_absent.so", "install it");
            FAIL("a missing library opened");
        } catch (const std::runtime_error& e) {
            const std::string what = e.what();
            CHECK(what.find("libmrjam_absent.so.9") != std::string::npos);
            CHECK(what.find("install it") != std::string::npos);
        }
    }
}
