#pragma once
// Raw little helpers for the checkpoint file: trivially copyable values and vectors of them.
#include <istream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace mrjam::binary {

template <class T>
void put(std::ostream& out, const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <class T>
T get(std::istream& in) {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    in.read(reinterpret_cast<char*>(&v), sizeof(T));
    if (!in) throw std::runtime_error("checkpoint is truncated or unreadable");
    return v;
}

template <class T>
void put_vector(std::ostream& out, const std::vector<T>& v) {
    put<std::uint64_t>(out, v.size());
    out.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(T)));
}

// Bytes left to read in a seekable stream (the largest value for one that is not).
inline std::uint64_t bytes_left(std::istream& in) {
    const auto here = in.tellg();
    if (here < 0) return ~0ull;
    in.seekg(0, std::ios::end);
    const auto end = in.tellg();
    in.seekg(here);
    return end >= here ? static_cast<std::uint64_t>(end - here) : 0;
}

template <class T>
void get_vector(std::istream& in, std::vector<T>& v) {
    const auto n = get<std::uint64_t>(in);
    // A damaged length must not become a huge allocation: the array has to fit in what is left.
    if (n > bytes_left(in) / sizeof(T))
        throw std::runtime_error("checkpoint is corrupt or truncated (an array of " + std::to_string(n) +
                                 " entries is longer than the rest of the file)");
    v.resize(n);
    in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(n * sizeof(T)));
    if (!in) throw std::runtime_error("checkpoint is truncated or unreadable");
}

inline void put_string(std::ostream& out, const std::string& s) {
    std::vector<char> v(s.begin(), s.end());
    put_vector(out, v);
}

inline std::string get_string(std::istream& in) {
    std::vector<char> v;
    get_vector(in, v);
    return std::string(v.begin(), v.end());
}

}  // namespace mrjam::binary
