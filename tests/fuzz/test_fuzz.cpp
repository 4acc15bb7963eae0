#include <doctest/doctest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "fuzz/fuzz_inputs.h"

// Bad input, made on purpose: a seeded mutation loop over valid OBJ files and scene files
// (byte flips, inserted tokens that parsers trip on, cut-off and repeated lines), and the
// corpus of inputs that once broke a parser (tests/fuzz/corpus), kept as regression cases.
// The same checks run under libFuzzer where clang is there (tools/fuzz).

using namespace pbdsplat;

namespace {

std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

const char* const k_tokens[] = {"nan", "-nan", "inf", "1e39", "-1e39", "0", "-0", "4294967296", "-2147483649", "99999999999999999999",
                                "//", "/", "f", "v", "vn", "vt", "#", "\n", " ", "\t", "=", "[", "]", "{", "}", "\"", "'",
                                "[[events]]", "[render]", "[model]", "type", "mesh", "1.5.5", "0x1F", "true", "\r\n", ",", "\\"};

std::string mutate(const std::string& seed, std::mt19937& rng) {
    std::string s = seed;
    const int edits = 1 + int(rng() % 6);
    for (int e = 0; e < edits; ++e) {
        const size_t at = s.empty() ? 0 : rng() % (s.size() + 1);
        switch (rng() % 6) {
        case 0: if (!s.empty() && at < s.size()) s[at] = char(rng() % 256); break;  // flip a byte
        case 1: s.insert(at, k_tokens[rng() % std::size(k_tokens)]); break;
        case 2: s = s.substr(0, at); break;  // cut off
        case 3: if (at < s.size()) s.erase(at, 1 + rng() % 16); break;
        case 4: {  // repeat a line
            const size_t start = s.rfind('\n', at == 0 ? 0 : at - 1);
            const size_t end = s.find('\n', at);
            const size_t a = start == std::string::npos ? 0 : start + 1;
            if (end != std::string::npos && end > a) s.insert(a, s.substr(a, end - a + 1));
            break;
        }
        default: {  // a number replaced by an extreme one
            const size_t d = s.find_first_of("0123456789", at);
            if (d != std::string::npos) s.replace(d, 1, k_tokens[rng() % 10]);
            break;
        }
        }
    }
    return s;
}

template <class Check>
void run_mutants(const std::vector<std::string>& seeds, int rounds, uint32_t seed, Check check, const char* what) {
    std::mt19937 rng(seed);
    for (int k = 0; k < rounds; ++k) {
        const std::string input = mutate(seeds[size_t(k) % seeds.size()], rng);
        const auto start = std::chrono::steady_clock::now();
        const std::string problem = check(input);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!problem.empty() || seconds > 2.0) {
            // Keep it: a failure found is a regression case once fixed (tests/fuzz/corpus).
            const auto path = std::filesystem::path(PBDSPLAT_TEST_OUTPUT_DIR) / (std::string("fuzz_") + what + "_" + std::to_string(k));
            std::filesystem::create_directories(path.parent_path());
            std::ofstream(path, std::ios::binary) << input;
            FAIL(std::string(what) << " mutant " << k << ": " << (problem.empty() ? "took " + std::to_string(seconds) + " s" : problem)
                      << " (input saved to " << path.string() << ")");
        }
    }
    MESSAGE(rounds << " " << std::string(what) << " mutants, each answered cleanly");
}

std::vector<std::string> files_in(const std::filesystem::path& dir, const std::string& ext) {
    std::vector<std::string> out;
    if (!std::filesystem::exists(dir)) return out;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().extension() == ext) out.push_back(read_file(e.path()));
    return out;
}

} // namespace

TEST_SUITE("fuzz/regression") {
    TEST_CASE("the corpus of inputs that once broke a parser gets clean answers") {
        const std::filesystem::path corpus = PBDSPLAT_FUZZ_CORPUS_DIR;
        size_t n = 0;
        for (const auto& e : std::filesystem::directory_iterator(corpus / "obj")) {
            INFO(e.path().string());
            CHECK(fuzz::check_obj(read_file(e.path())) == "");
            ++n;
        }
        for (const auto& e : std::filesystem::directory_iterator(corpus / "scene")) {
            INFO(e.path().string());
            CHECK(fuzz::check_scene(read_file(e.path())) == "");
            ++n;
        }
        REQUIRE(n >= 10);
        MESSAGE(n << " corpus inputs");
    }

    TEST_CASE("mutated OBJ files: accepted as valid meshes or refused with the input named") {
        std::vector<std::string> seeds = files_in(std::filesystem::path(PBDSPLAT_FUZZ_CORPUS_DIR) / "obj", ".obj");
        seeds.push_back("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n");
        seeds.push_back("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -1 -2 -3\n");
        run_mutants(seeds, 4000, 1234u, fuzz::check_obj, "obj");
    }

    TEST_CASE("mutated scene files: accepted and written back, or refused with the input named") {
        std::vector<std::string> seeds = files_in(std::filesystem::path(PBDSPLAT_FUZZ_CORPUS_DIR) / "scene", ".toml");
        for (const auto& s : files_in(PBDSPLAT_PROJECT_SCENES_DIR, ".toml")) seeds.push_back(s);
        REQUIRE(!seeds.empty());
        run_mutants(seeds, 3000, 4321u, fuzz::check_scene, "scene");
    }
}
