#pragma once
// A shared library opened at run time (dlopen) for a dependency only some commands need, so the
// others do not pay for loading it: gmsh (magnetics/gmsh_api.cpp) and librsvg with cairo
// (io/svg_raster.cpp). Opened by its soname, then by the file CMake found; kept open for the
// process (the libraries keep global state).
#include <dlfcn.h>

#include <stdexcept>
#include <string>

namespace mrjam {

class SharedLibrary {
public:
    // Throws Error naming the library, the loader's reason and `fix`.
    template <class Error>
    static SharedLibrary open(const char* soname, const char* path, const std::string& fix) {
        for (const char* name : {soname, path})
            if (void* handle = dlopen(name, RTLD_NOW | RTLD_LOCAL)) return SharedLibrary(handle, soname);
        const char* why = dlerror();
        throw Error(std::string(soname) + " could not be loaded (" + (why ? why : "unknown reason") + "): " + fix);
    }

    // The function `name` (searched in the library and the libraries it depends on), as `pointer`'s
    // type; throws Error naming it when missing.
    template <class Error, class F>
    void resolve(F& pointer, const char* name, const std::string& fix) const {
        pointer = reinterpret_cast<F>(dlsym(handle_, name));
        if (!pointer) throw Error(soname_ + " has no " + name + ": " + fix);
    }

private:
    SharedLibrary(void* handle, std::string soname) : handle_(handle), soname_(std::move(soname)) {}
    void* handle_;
    std::string soname_;
};

}  // namespace mrjam
