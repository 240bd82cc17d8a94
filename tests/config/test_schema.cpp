// The declarative schema (config/schema.hpp) and the strict reader under it: suggestions by
// edit distance, strict reading, and the print -> read round trip.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <random>

#include "config/schema.hpp"

namespace st {
namespace {

TEST(EditDistance, CountsInsertionsDeletionsSubstitutions) {
  EXPECT_EQ(editDistance("fov_dg", "fov_deg"), 1);
  EXPECT_EQ(editDistance("kitten", "sitting"), 3);
  EXPECT_EQ(editDistance("", "abc"), 3);
  EXPECT_EQ(editDistance("abc", "abc"), 0);
  EXPECT_EQ(editDistance("qe", "eq"), 2);
}

TEST(EditDistance, SuggestsOnlyNearKeys) {
  const std::vector<std::string> keys = {"fov_deg", "fx", "fy", "resolution", "dist"};
  EXPECT_EQ(closestKey("fov_dg", keys), "fov_deg");
  EXPECT_EQ(closestKey("resolutoin", keys), "resolution");
  EXPECT_EQ(closestKey("distortion_coefficients", keys), "");  // a different word
}

struct Demo {
  double a = 1.5;
  int n = 3;
  uint64_t seed = 7;
  bool on = true;
  std::string name = "x", mode = "fast", label = "L";
  std::vector<double> list = {1, 2};
  std::vector<std::string> words;
  Vec2 v2 = Vec2(1, 2);
  Vec3 v3 = Vec3(0, 0, 1);
  std::vector<std::pair<double, double>> spans;
  double need = 0;
};

const SectionSchema<Demo>& demoSchema() {
  static const auto s = SectionSchema<Demo>()
                            .add("a", &Demo::a, "a number")
                            .alias("a_milli", &Demo::a, 1e-3, "a in thousandths")
                            .add("n", &Demo::n, "an integer")
                            .add("seed", &Demo::seed, "a seed")
                            .add("on", &Demo::on, "a flag")
                            .add("name", &Demo::name, "a name")
                            .choice("mode", &Demo::mode, {"fast", "slow"}, "a mode")
                            .add("label", &Demo::label, "a label; empty = none")
                            .add("list", &Demo::list, "numbers")
                            .add("words", &Demo::words, "words")
                            .add("v2", &Demo::v2, "x y")
                            .add("v3", &Demo::v3, "x y z")
                            .add("spans", &Demo::spans, "t0 t1 ...")
                            .add("need", &Demo::need, "required number")
                            .required();
  return s;
}

std::string errorOf(const std::string& text, bool mrpt_safe = false) {
  const mrpt::config::CConfigFileMemory cfg(text);
  Demo d;
  try {
    demoSchema().read(IniReader{cfg, "demo.ini", mrpt_safe}, "S", d);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SectionSchema, UnknownKeyNamesFileSectionKeyAndSuggestion) {
  EXPECT_EQ(errorOf("[S]\nneed = 1\nseeed = 3\n"),
            "demo.ini: [S] key 'seeed': unknown key; did you mean 'seed'?");
  // No near key: the known keys are listed instead of a wild guess.
  EXPECT_NE(errorOf("[S]\nneed = 1\ncompletely_different = 3\n").find("(known: a, a_milli,"),
            std::string::npos);
  // Through MRPT's stacked exceptions the message must not contain ']' before the key.
  const std::string safe = errorOf("[S]\nneed = 1\nseeed = 3\n", true);
  EXPECT_EQ(safe, "demo.ini: section 'S' key 'seeed': unknown key; did you mean 'seed'?");
}

TEST(SectionSchema, RequiredBadValuesAndChoicesNameTheKey) {
  EXPECT_NE(errorOf("[S]\na = 2\n").find("[S] key 'need': missing key"), std::string::npos);
  EXPECT_NE(errorOf("[S]\nneed = 1\nn = 2.5\n").find("[S] n: not an integer"), std::string::npos);
  EXPECT_NE(errorOf("[S]\nneed = 1\na = 1x\n").find("[S] a = '1x': not a number"), std::string::npos);
  EXPECT_NE(errorOf("[S]\nneed = 1\nseed = -1\n").find("[S] seed"), std::string::npos);
  EXPECT_NE(errorOf("[S]\nneed = 1\nv3 = 1 2\n").find("key 'v3': expected three numbers"),
            std::string::npos);
  EXPECT_NE(errorOf("[S]\nneed = 1\nspans = 1 2 3\n").find("key 'spans': must hold pairs"),
            std::string::npos);
  EXPECT_EQ(errorOf("[S]\nneed = 1\nmode = slwo\n"),
            "demo.ini: [S] key 'mode' = 'slwo': expected one of fast, slow; did you mean 'slow'?");
  EXPECT_EQ(errorOf("[S]\nneed = 1\n"), "");
}

TEST(SectionSchema, DefaultsComeFromTheStructAndAliasesScale) {
  const mrpt::config::CConfigFileMemory cfg("[S]\nneed = 4\na_milli = 250\n");
  Demo d;
  demoSchema().read(IniReader{cfg, "demo.ini"}, "S", d);
  EXPECT_EQ(d.need, 4);
  EXPECT_DOUBLE_EQ(d.a, 0.25);
  EXPECT_EQ(d.n, 3);
  EXPECT_EQ(d.mode, "fast");
  const std::string printed = demoSchema().print("S", d);
  EXPECT_EQ(printed.find("a_milli"), std::string::npos) << "aliases are not printed";
  EXPECT_NE(printed.find("# an integer\nn = 3\n"), std::string::npos) << printed;
}

TEST(SectionSchema, PrintReadsBackToTheSameValues) {
  Demo d;
  d.a = 0.1 + 0.2;  // needs 17 digits
  d.n = -12;
  d.seed = 18446744073709551615ull;
  d.on = false;
  d.name = "some name";
  d.mode = "slow";
  d.label = "";  // empty differs from the default "L" and must survive
  d.list = {};   // likewise the empty list against the default {1, 2}
  d.words = {"pyramid", "voting"};
  d.v2 = Vec2(-3.25, 1e-300);
  d.v3 = Vec3(1.0 / 3, 2.0 / 3, -1e10);
  d.spans = {{0.5, 1}, {2, 2.75}};
  d.need = 42;
  const std::string text = demoSchema().print("S", d);
  const mrpt::config::CConfigFileMemory cfg(text);
  Demo back;
  demoSchema().read(IniReader{cfg, "printed"}, "S", back);
  EXPECT_EQ(back.a, d.a);
  EXPECT_EQ(back.n, d.n);
  EXPECT_EQ(back.seed, d.seed);
  EXPECT_EQ(back.on, d.on);
  EXPECT_EQ(back.name, d.name);
  EXPECT_EQ(back.mode, d.mode);
  EXPECT_EQ(back.label, d.label);
  EXPECT_EQ(back.list, d.list);
  EXPECT_EQ(back.words, d.words);
  EXPECT_EQ(back.v2, d.v2);
  EXPECT_EQ(back.v3, d.v3);
  EXPECT_EQ(back.spans, d.spans);
  EXPECT_EQ(back.need, d.need);
  EXPECT_EQ(demoSchema().print("S", back), text);
}

TEST(IniNumbers, ShortestFormReadsBackExactly) {
  EXPECT_EQ(formatIniNumber(0.1), "0.1");
  EXPECT_EQ(formatIniNumber(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(formatIniNumber(20000), "20000");
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  for (int i = 0; i < 2000; ++i) {
    const double v = u(rng) * std::pow(10.0, static_cast<int>(rng() % 40) - 20);
    EXPECT_EQ(std::strtod(formatIniNumber(v).c_str(), nullptr), v);
  }
}

}  // namespace
}  // namespace st
