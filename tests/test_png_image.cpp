// The PNG writer (lib/io/png_image.hpp), checked by decoding its files here with independent
// code: chunk walk, bitwise CRC-32, a stored-block-only inflater and a plain Adler-32.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/png_image.hpp"
#include "test_support.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes read_bytes(const std::string& path) {
    const std::string s = mrjam_test::slurp(path);
    return Bytes(s.begin(), s.end());
}

std::uint32_t be32(const Bytes& b, std::size_t at) {
    REQUIRE(at + 4 <= b.size());
    return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) | (std::uint32_t{b[at + 2]} << 8) |
           std::uint32_t{b[at + 3]};
}

// CRC-32 bit by bit, straight from the definition (PNG spec annex D without the table).
std::uint32_t crc32_bitwise(const std::uint8_t* p, std::size_t n) {
    std::uint32_t c = 0xFFFFFFFFu;
    for (std::size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return c ^ 0xFFFFFFFFu;
}

std::uint32_t adler32_plain(const Bytes& d) {
    std::uint32_t a = 1, b = 0;
    for (const std::uint8_t x : d) {
        a = (a + x) % 65521;
        b = (b + a) % 65521;
    }
    return (b << 16) | a;
}

struct Chunk {
    std::string type;
    Bytes data;
};

// Walks the chunks after the signature, checking each CRC; stops after IEND.
std::vector<Chunk> read_chunks(const Bytes& file) {
    const Bytes signature{0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    REQUIRE(file.size() >= signature.size());
    CHECK(Bytes(file.begin(), file.begin() + 8) == signature);
    std::vector<Chunk> chunks;
    std::size_t pos = 8;
    while (pos < file.size()) {
        const std::uint32_t len = be32(file, pos);
        REQUIRE(pos + 12 + len <= file.size());
        Chunk c{std::string(file.begin() + static_cast<std::ptrdiff_t>(pos + 4),
                            file.begin() + static_cast<std::ptrdiff_t>(pos + 8)),
                Bytes(file.begin() + static_cast<std::ptrdiff_t>(pos + 8),
                      file.begin() + static_cast<std::ptrdiff_t>(pos + 8 + len))};
        CAPTURE(c.type);
        CHECK(crc32_bitwise(file.data() + pos + 4, len + 4) == be32(file, pos + 8 + len));
        pos += 12 + len;
        chunks.push_back(std::move(c));
        if (chunks.back().type == "IEND") break;
    }
    CHECK(pos == file.size());  // nothing after IEND
    return chunks;
}

// Inflates a zlib stream made only of stored blocks (RFC 1950/1951); fails the test on anything
// else. `block_sizes` receives each block's LEN.
Bytes inflate_stored(const Bytes& z, std::vector<std::size_t>& block_sizes) {
    REQUIRE(z.size() >= 2 + 4);
    CHECK((z[0] & 0x0F) == 8);              // CM = deflate
    CHECK((z[0] >> 4) <= 7);                // window <= 32 KiB
    CHECK(((z[0] << 8) | z[1]) % 31 == 0);  // FCHECK
    CHECK((z[1] & 0x20) == 0);              // no preset dictionary
    Bytes out;
    std::size_t pos = 2;
    bool final = false;
    while (!final) {
        REQUIRE(pos + 5 <= z.size());
        final = z[pos] & 1;
        REQUIRE(((z[pos] >> 1) & 3) == 0);  // BTYPE 00: stored; the rest of the byte is padding
        const std::size_t len = z[pos + 1] | (z[pos + 2] << 8), nlen = z[pos + 3] | (z[pos + 4] << 8);
        CHECK(len == (~nlen & 0xFFFF));
        pos += 5;
        REQUIRE(pos + len <= z.size());
        out.insert(out.end(), z.begin() + static_cast<std::ptrdiff_t>(pos),
                   z.begin() + static_cast<std::ptrdiff_t>(pos + len));
        block_sizes.push_back(len);
        pos += len;
    }
    REQUIRE(pos + 4 == z.size());
    CHECK(be32(z, pos) == adler32_plain(out));
    return out;
}

// A deterministic image whose bytes differ from pixel to pixel.
mrjam::RgbImage pattern(int w, int h) {
    mrjam::RgbImage img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.set(x, y,
                    {static_cast<std::uint8_t>(x * 7 + y), static_cast<std::uint8_t>(y * 13 + 5),
                     static_cast<std::uint8_t>((x ^ y) * 3)});
    return img;
}

// The expected decoded IDAT: filter byte 0, then the row's RGB bytes, top row first.
Bytes expected_scanlines(const mrjam::RgbImage& img) {
    Bytes out;
    for (int y = 0; y < img.height; ++y) {
        out.push_back(0);
        for (int x = 0; x < img.width; ++x)
            for (const std::uint8_t v : img.get(x, y)) out.push_back(v);
    }
    return out;
}

// Writes, reads back and checks the whole file; returns the stored block sizes.
std::vector<std::size_t> round_trip(const mrjam::RgbImage& img) {
    mrjam_test::TempDir dir("mrjam_png");
    const std::string path = dir.file("image.png");
    mrjam::write_png(path, img);
    const Bytes file = read_bytes(path);
    CHECK(file == mrjam::encode_png(img));
    const std::vector<Chunk> chunks = read_chunks(file);
    REQUIRE(chunks.size() >= 3);
    REQUIRE(chunks.front().type == "IHDR");
    REQUIRE(chunks.back().type == "IEND");
    CHECK(chunks.back().data.empty());

    const Bytes& ihdr = chunks.front().data;
    REQUIRE(ihdr.size() == 13);
    CHECK(be32(ihdr, 0) == static_cast<std::uint32_t>(img.width));
    CHECK(be32(ihdr, 4) == static_cast<std::uint32_t>(img.height));
    CHECK(ihdr[8] == 8);   // bit depth
    CHECK(ihdr[9] == 2);   // colour type RGB
    CHECK(ihdr[10] == 0);  // compression: deflate
    CHECK(ihdr[11] == 0);  // filter method 0
    CHECK(ihdr[12] == 0);  // no interlace

    Bytes idat;  // IDAT chunks are consecutive and concatenate into one zlib stream
    for (std::size_t i = 1; i + 1 < chunks.size(); ++i) {
        CHECK(chunks[i].type == "IDAT");
        idat.insert(idat.end(), chunks[i].data.begin(), chunks[i].data.end());
    }
    std::vector<std::size_t> blocks;
    CHECK(inflate_stored(idat, blocks) == expected_scanlines(img));
    return blocks;
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("png: small image round-trips through signature, IHDR, CRCs and the zlib stream") {
        const auto blocks = round_trip(pattern(5, 3));
        CHECK(blocks == std::vector<std::size_t>{3 * (5 * 3 + 1)});
        round_trip(pattern(1, 1));
    }

    TEST_CASE("png: image data above 65535 bytes splits into full stored blocks plus the rest") {
        const mrjam::RgbImage img = pattern(200, 150);  // (600 + 1) * 150 = 90150 bytes
        CHECK(round_trip(img) == std::vector<std::size_t>{65535, 90150 - 65535});
        // Exactly two full blocks (131070 = 10 * 13107 bytes): no empty trailing block may follow.
        CHECK(round_trip(pattern(3, 13107)) == std::vector<std::size_t>{65535, 65535});
        // One byte over a block boundary, inside a single row: (3 * 21845 + 1) * 1 = 65536.
        CHECK(round_trip(pattern(21845, 1)) == std::vector<std::size_t>{65535, 1});
    }

    TEST_CASE("png: errors name the path; malformed images are refused") {
        mrjam_test::TempDir dir("mrjam_png");
        const std::string bad = dir.file("no_such_dir/out.png");
        try {
            mrjam::write_png(bad, pattern(2, 2));
            FAIL("expected std::runtime_error");
        } catch (const std::runtime_error& e) {
            CHECK(std::string(e.what()).find(bad) != std::string::npos);
        }
        mrjam::RgbImage broken = pattern(2, 2);
        broken.rgb.pop_back();
        CHECK_THROWS_AS(mrjam::encode_png(broken), std::invalid_argument);
        CHECK_THROWS_AS(mrjam::encode_png(mrjam::RgbImage{}), std::invalid_argument);
    }

    TEST_CASE("png: viridis endpoints, clamping and monotone lightness") {
        using Rgb = std::array<std::uint8_t, 3>;
        CHECK(mrjam::viridis(0) == Rgb{68, 1, 84});
        CHECK(mrjam::viridis(1) == Rgb{253, 231, 37});
        CHECK(mrjam::viridis(-3) == mrjam::viridis(0));
        CHECK(mrjam::viridis(7) == mrjam::viridis(1));
        CHECK(mrjam::viridis(std::nan("")) == mrjam::viridis(0));
        CHECK(mrjam::viridis(0.5) == Rgb{33, 144, 141});
        // Viridis is designed with lightness increasing monotonically; the green channel carries most
        // of it and must never decrease along the map.
        int previous = -1;
        for (int i = 0; i <= 100; ++i) {
            const int g = mrjam::viridis(i / 100.0)[1];
            CHECK(g >= previous);
            previous = g;
        }
    }

    TEST_CASE("png: scalar map puts row y = 0 at the bottom, NaN grey, colour bar on the right") {
        const int nx = 3, ny = 2, ppc = 4;
        const double nan = std::numeric_limits<double>::quiet_NaN();
        // x fastest: row y = 0 is {0, 1, 2}, row y = 1 is {3, NaN, 10 (clamped to vmax)}.
        const std::vector<double> values{0, 1, 2, 3, nan, 10};
        const mrjam::RgbImage plain = mrjam::render_scalar_map(values, nx, ny, 0, 4, ppc, false);
        CHECK(plain.width == nx * ppc);
        CHECK(plain.height == ny * ppc);
        auto cell = [&](const mrjam::RgbImage& img, int i, int j, int dx, int dy) {
            return img.get(i * ppc + dx, (ny - 1 - j) * ppc + dy);
        };
        for (const int d : {0, ppc - 1}) {  // every corner pixel of each cell
            CHECK(cell(plain, 0, 0, d, d) == mrjam::viridis(0));
            CHECK(cell(plain, 1, 0, d, 0) == mrjam::viridis(0.25));
            CHECK(cell(plain, 2, 0, 0, d) == mrjam::viridis(0.5));
            CHECK(cell(plain, 0, 1, d, d) == mrjam::viridis(0.75));
            CHECK(cell(plain, 1, 1, d, d) == std::array<std::uint8_t, 3>{128, 128, 128});
            CHECK(cell(plain, 2, 1, d, d) == mrjam::viridis(1));
        }
        CHECK(plain.get(0, plain.height - 1) == mrjam::viridis(0));  // bottom-left pixel is value[0]

        const mrjam::RgbImage bar = mrjam::render_scalar_map(values, nx, ny, 0, 4, ppc, true);
        CHECK(bar.width > plain.width);
        CHECK(bar.height == plain.height);
        CHECK(bar.get(bar.width - 1, 0) == mrjam::viridis(1));                         // top of the bar: vmax
        CHECK(bar.get(bar.width - 1, bar.height - 1) == mrjam::viridis(0));            // bottom: vmin
        CHECK(bar.get(plain.width, 0) == std::array<std::uint8_t, 3>{255, 255, 255});  // the gap
        for (int y = 0; y < plain.height; ++y)
            for (int x = 0; x < plain.width; ++x) CHECK(bar.get(x, y) == plain.get(x, y));

        round_trip(bar);
        CHECK_THROWS_AS(mrjam::render_scalar_map(values, 4, 2, 0, 1, 1, false), std::invalid_argument);
        CHECK_THROWS_AS(mrjam::render_scalar_map(values, nx, ny, 1, 0, 1, false), std::invalid_argument);
        CHECK_THROWS_AS(mrjam::render_scalar_map(values, nx, ny, 0, 1, 0, false), std::invalid_argument);
    }
}
