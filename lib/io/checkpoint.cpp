#include "io/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "core/binary_io.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {
namespace {

// "MRJAMCK9" (3: the Lees-Edwards state; 4: magnetic pass counts; 5: held magnetic forces;
// 6: held carrier-flow lookups; 7: a checksum; 8: each force term's state under its name, in
// the list's order; 9: a neighbour list's range cap). Older files are refused by name: their
// term state was laid out by the checkpoint code itself, which no longer knows any term's state.
constexpr std::uint64_t kMagic = 0x394b434d414a524dull;
constexpr std::uint64_t kMagicPrefix = 0x004b434d414a524dull;  // "MRJAMCK" and any version byte
constexpr int kVersion = 9;

void put_particles(std::ostream& out, const Particles& p) {
    p.for_each_array([&](const auto& a) { binary::put_vector(out, a); });
}

void get_particles(std::istream& in, Particles& p) {
    p.for_each_array([&](auto& a) { binary::get_vector(in, a); });
    // Every per-grain array must have one entry per grain: a damaged file that does not would
    // have the force passes index past an array's end. (The held forces, flow lookups and wall
    // histories are checked against the grain count where they are used, and renewed.)
    const std::size_t n = p.size();
    p.for_each_array([&](const auto& a) {
        if (a.size() != n) throw std::runtime_error("checkpoint is corrupt (per-grain arrays of different lengths)");
    });
}

// FNV-1a over a file's bytes up to `length`. Each step is a bijection of the running state, so
// any one changed byte changes the sum. At 2.4 ns per byte a standard-tier jam checkpoint (23 MB)
// is summed in 55 ms, small beside the run it resumes.
std::uint64_t file_checksum(const std::string& path, std::uint64_t length) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> buffer(1 << 20);
    std::uint64_t sum = 0xcbf29ce484222325ull;
    while (length > 0 && in) {
        in.read(buffer.data(), static_cast<std::streamsize>(std::min<std::uint64_t>(length, buffer.size())));
        const auto got = static_cast<std::size_t>(in.gcount());
        for (std::size_t k = 0; k < got; ++k) sum = (sum ^ static_cast<unsigned char>(buffer[k])) * 0x100000001b3ull;
        length -= got;
        if (got == 0) break;
    }
    if (length != 0) throw std::runtime_error("checkpoint is truncated or unreadable");
    return sum;
}

std::uint64_t file_size(const std::string& path) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) throw std::runtime_error("cannot open checkpoint " + path);
    return size;
}

// Opens a checkpoint past its magic number. The file ends in the checksum of everything before
// it, checked here before a byte of it is used.
std::ifstream open_and_check(const std::string& path, int& version) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open checkpoint " + path);
    const auto magic = binary::get<std::uint64_t>(in);
    if ((magic & 0x00ffffffffffffffull) != kMagicPrefix) throw std::runtime_error(path + " is not an mrjam checkpoint");
    version = static_cast<int>((magic >> 56) - '0');
    if (version != kVersion)
        throw SceneError("--resume",
                         path + ": " + "checkpoint format " + std::to_string(version) + " was written by " +
                             (version < kVersion ? "an older" : "a newer") + " mrjam, and this one reads format " +
                             std::to_string(kVersion) +
                             " only (each force term saves its own state since 8); rerun the scene from the start");
    {
        const std::uint64_t size = file_size(path);
        if (size < 2 * sizeof(std::uint64_t)) throw std::runtime_error("checkpoint is truncated or unreadable");
        const std::uint64_t body = size - sizeof(std::uint64_t);
        std::ifstream tail(path, std::ios::binary);
        tail.seekg(static_cast<std::streamoff>(body));
        if (binary::get<std::uint64_t>(tail) != file_checksum(path, body))
            throw std::runtime_error("checkpoint is corrupt (its checksum does not match its contents)");
    }
    return in;
}

// The state ends where the checksum begins: anything else is a damaged file that happened to parse.
void check_read_to_end(std::istream& in, const std::string& path) {
    const auto here = in.tellg();
    if (here < 0 || static_cast<std::uint64_t>(here) + sizeof(std::uint64_t) != file_size(path))
        throw std::runtime_error("checkpoint is corrupt (its state does not end where its checksum begins)");
}

// A checkpoint that cannot be read (missing, damaged, not a checkpoint) is bad input to
// --resume, named with its file (exit 2), for every mode that resumes one.
template <class Read>
auto as_resume_input(const std::string& path, Read&& read) {
    try {
        return read();
    } catch (const SceneError&) {
        throw;
    } catch (const std::runtime_error& e) {
        throw SceneError("--resume", path + ": " + e.what() + "; resume from an intact checkpoint");
    }
}

}  // namespace

void sync_to_disk(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) return;  // nothing there to make durable
    ::fsync(fd);
    ::close(fd);
}

namespace {

std::string directory_of(const std::string& path) {
    const std::filesystem::path p(path);
    return p.has_parent_path() ? p.parent_path().string() : std::string(".");
}

}  // namespace

void write_checkpoint(const std::string& path, const nlohmann::json& resolved_scene, const System& s,
                      const ProtocolPosition& position, const nlohmann::json& history) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw std::runtime_error("cannot write checkpoint " + tmp);
        binary::put(out, kMagic);
        binary::put_string(out, resolved_scene.dump());
        binary::put_string(out, history.dump());
        binary::put(out, position);
        binary::put(out, s.time);
        binary::put(out, s.step);
        binary::put(out, s.dt);
        // The Lees-Edwards offset is state (it integrates the rate over time); the flag and the
        // image velocity come with it so a resumed run needs nothing from the protocol to slide.
        binary::put<std::uint8_t>(out, s.domain.lees_edwards ? 1 : 0);
        binary::put(out, s.domain.shear_offset);
        binary::put(out, s.domain.shear_velocity);
        put_particles(out, s.particles);
        s.contacts.save(out);
        binary::put<std::uint64_t>(out, s.terms.size());
        for (const auto& term : s.terms) {
            binary::put_string(out, term->name());
            term->save(s, out);
        }
        binary::put<std::uint64_t>(out, s.walls.size());
        for (const Wall& w : s.walls) {
            binary::put(out, w.point);
            binary::put(out, w.velocity);
            binary::put_vector(out, w.history);
        }
        binary::put<std::uint64_t>(out, s.rafts.size());
        for (const Raft& r : s.rafts) {
            binary::put_string(out, r.name);
            binary::put(out, r.velocity);
            binary::put(out, r.members);
        }
        if (!out) throw std::runtime_error("failed writing checkpoint " + tmp);
    }
    // The checksum is summed from the file as written, so it also vouches for the write.
    {
        const std::uint64_t sum = file_checksum(tmp, file_size(tmp));
        std::ofstream out(tmp, std::ios::binary | std::ios::app);
        binary::put(out, sum);
        if (!out) throw std::runtime_error("failed writing checkpoint " + tmp);
    }
    // On disk before it replaces the last good checkpoint, and the rename on disk after: a power
    // loss then leaves the old checkpoint or the new one, never a file the rename points at but
    // the disk never got.
    sync_to_disk(tmp);
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
        throw std::runtime_error("cannot move checkpoint into place at " + path);
    sync_to_disk(directory_of(path));
}

CheckpointHeader read_checkpoint_header(const std::string& path) {
    return as_resume_input(path, [&] {
        int version = 0;
        std::ifstream in = open_and_check(path, version);
        CheckpointHeader h;
        h.version = version;
        try {
            h.resolved_scene = nlohmann::json::parse(binary::get_string(in));
            h.history = nlohmann::json::parse(binary::get_string(in));
        } catch (const nlohmann::json::exception& e) {
            throw std::runtime_error("checkpoint " + path + " is corrupt: " + e.what());
        }
        h.position = binary::get<ProtocolPosition>(in);
        return h;
    });
}

void restore_state(const std::string& path, System& s) {
    as_resume_input(path, [&] {
        int version = 0;
        std::ifstream in = open_and_check(path, version);
        binary::get_string(in);
        binary::get_string(in);
        binary::get<ProtocolPosition>(in);
        s.time = binary::get<double>(in);
        s.step = binary::get<long>(in);
        s.dt = binary::get<double>(in);
        s.domain.lees_edwards = binary::get<std::uint8_t>(in) != 0;
        s.domain.shear_offset = binary::get<double>(in);
        s.domain.shear_velocity = binary::get<double>(in);
        get_particles(in, s.particles);
        s.contacts.load(in);
        // The scene rebuilt the same terms in the same order; each reads back its own state.
        if (binary::get<std::uint64_t>(in) != s.terms.size())
            throw std::runtime_error("checkpoint " + path + " does not match its scene's force terms");
        for (auto& term : s.terms) {
            if (binary::get_string(in) != term->name())
                throw std::runtime_error("checkpoint " + path + " does not match its scene's force terms (expected '" +
                                         term->name() + "')");
            term->load(s, in);
        }
        const auto nwalls = binary::get<std::uint64_t>(in);
        if (nwalls != s.walls.size())
            throw std::runtime_error("checkpoint " + path + " does not match its scene's walls");
        for (Wall& w : s.walls) {
            w.point = binary::get<Vec3>(in);
            w.velocity = binary::get<Vec3>(in);
            binary::get_vector(in, w.history);
            w.near.valid = false;  // found again at the next neighbour rebuild
        }
        const auto nrafts = binary::get<std::uint64_t>(in);
        s.rafts.clear();
        for (std::uint64_t r = 0; r < nrafts; ++r) {
            Raft raft;
            raft.name = binary::get_string(in);
            raft.velocity = binary::get<Vec3>(in);
            raft.members = binary::get<std::size_t>(in);
            s.rafts.push_back(raft);
        }
        check_read_to_end(in, path);
    });
}

void restore_scene(const std::string& path, Scene& scene) {
    restore_state(path, scene.system);
    choose_timestep(scene);
    restore_state(path, scene.system);
}

}  // namespace mrjam
