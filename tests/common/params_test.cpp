// The parameter visitor (common/params.h): one visit() serves YAML in, YAML out, validation,
// equality and descriptions, checked on a small struct with every kind of field.

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "canopy/common/params.h"
#include "canopy/common/warning.h"

using namespace canopy;

namespace {

enum class Mode { kFast, kSlow };
inline constexpr EnumName<Mode> kModeNames[] = {{Mode::kFast, "fast"}, {Mode::kSlow, "slow"}};

struct Item {
  std::string name;
  int weight = 1;
  template <class A>
  void visit(A& a) {
    a.required("name", name, "Name of the item");
    a("weight", weight, limits::in(1, 9), "Weight");
  }
};

struct Inner {
  double low_m = 0.1;
  double high_m = 0.5;
  template <class A>
  void visit(A& a) {
    a("low_m", low_m, limits::positive(), "Lower bound [m]");
    a("high_m", high_m, limits::positive(), "Upper bound [m]");
    a.check(high_m >= low_m, "high_m", "must be >= low_m");
  }
};

struct Outer {
  double rate = 0.25;
  float gain = -0.1f;
  int count = 3;
  std::uint64_t seed = 7;
  bool enabled = true;
  std::string planner = "a";
  Mode mode = Mode::kFast;
  std::vector<double> heights_m = {0.4, 1.0};
  Inner inner;
  std::vector<Item> items = {{"x", 2}};

  template <class A>
  void visit(A& a) {
    a("rate", rate, limits::in(0.0, 1.0), "A probability");
    a("gain", gain, limits::finite(), "A float");
    a("count", count, limits::in(1, 100), "A count");
    a("seed", seed, limits::non_negative(), "A seed");
    a("enabled", enabled, "A switch");
    a.one_of("planner", planner, {"a", "b"}, "A name from a list");
    a.choice("mode", mode, kModeNames, "An enum");
    a("heights_m", heights_m, limits::open(0.0, 2.0), "A list of heights [m]");
    a.section("inner", inner, "A nested struct");
    a.list("items", items, "A list of structs");
  }
};

Outer read(const std::string& text, const std::string& name = "t.yaml") {
  YamlReader y = YamlReader::load_string(text, name);
  Outer o = params_from_yaml<Outer>(y);
  y.finish();
  return o;
}

std::string error_of(const std::string& text) {
  try {
    read(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(Params, LimitsSayWhatTheyWant) {
  EXPECT_EQ(limits::finite().text(), "must be a finite number");
  EXPECT_EQ(limits::positive().text(), "must be > 0");
  EXPECT_EQ(limits::non_negative().text(), "must be >= 0");
  EXPECT_EQ(limits::negative().text(), "must be < 0");
  EXPECT_EQ(limits::in(0, 1).text(), "must be in [0, 1]");
  EXPECT_EQ(limits::above_up_to(0, 1).text(), "must be in (0, 1]");
  EXPECT_EQ(limits::open(-90, 90).text(), "must be in (-90, 90)");
  EXPECT_TRUE(limits::in(0, 1).ok(1.0));
  EXPECT_FALSE(limits::above_up_to(0, 1).ok(0.0));
  EXPECT_FALSE(limits::finite().ok(std::nan("")));
  EXPECT_FALSE(limits::at_least(1).ok(std::numeric_limits<double>::infinity()));
}

TEST(Params, AbsentKeysKeepTheirValuesGivenOnesAreRead) {
  const Outer d = read("{}");
  EXPECT_TRUE(same_params(d, Outer{}));
  const Outer o = read(
      "rate: 0.5\ngain: 2.5\ncount: 4\nseed: 18446744073709551615\nenabled: false\nplanner: b\nmode: slow\n"
      "heights_m: [0.5]\ninner: {low_m: 0.2}\nitems: [{name: y}, {name: z, weight: 9}]\n");
  EXPECT_EQ(o.rate, 0.5);
  EXPECT_EQ(o.gain, 2.5f);
  EXPECT_EQ(o.count, 4);
  EXPECT_EQ(o.seed, 18446744073709551615ull);
  EXPECT_FALSE(o.enabled);
  EXPECT_EQ(o.planner, "b");
  EXPECT_EQ(o.mode, Mode::kSlow);
  EXPECT_EQ(o.heights_m, std::vector<double>{0.5});
  EXPECT_EQ(o.inner.low_m, 0.2);
  EXPECT_EQ(o.inner.high_m, 0.5);
  ASSERT_EQ(o.items.size(), 2u);
  EXPECT_EQ(o.items[0].name, "y");
  EXPECT_EQ(o.items[0].weight, 1);  // a new item starts from the item's defaults
  EXPECT_EQ(o.items[1].weight, 9);
}

TEST(Params, BadValuesNameTheFileKeyAndValue) {
  EXPECT_EQ(error_of("rate: 1.5"), "t.yaml: key 'rate': value '1.5' must be in [0, 1]");
  EXPECT_EQ(error_of("rate: .nan"), "t.yaml: key 'rate': value '.nan' must be in [0, 1]");
  EXPECT_EQ(error_of("count: 2.5"), "t.yaml: key 'count': value '2.5' must be a whole number");
  EXPECT_EQ(error_of("count: 0"), "t.yaml: key 'count': value '0' must be in [1, 100]");
  EXPECT_EQ(error_of("count: 99999999999999999999"), "t.yaml: key 'count': value '99999999999999999999' must be in [1, 100]");
  EXPECT_EQ(error_of("seed: -1"), "t.yaml: key 'seed': value '-1' must be >= 0");
  EXPECT_EQ(error_of("seed: 18446744073709551616"), "t.yaml: key 'seed': value '18446744073709551616' must be >= 0");
  EXPECT_EQ(error_of("planner: c"), "t.yaml: key 'planner': value 'c' must be one of: a, b");
  EXPECT_EQ(error_of("mode: medium"), "t.yaml: key 'mode': value 'medium' must be one of: fast, slow");
  EXPECT_EQ(error_of("heights_m: [0.5, 2.0]"), "t.yaml: key 'heights_m': value '[0.5, 2.0]' holds a value that must be in (0, 2)");
  EXPECT_EQ(error_of("heights_m: 0.5"), "t.yaml: key 'heights_m': value '0.5' must be a list of numbers");
  EXPECT_EQ(error_of("inner: {low_m: 0.9}"), "t.yaml: key 'inner.high_m' (not given) must be >= low_m");
  EXPECT_EQ(error_of("inner: {lo_m: 0.9}"), "t.yaml: unknown key 'inner.lo_m'");
  EXPECT_EQ(error_of("items: [{weight: 2}]"), "t.yaml: missing key 'items[0].name'");
  EXPECT_EQ(error_of("items: []"), "t.yaml: key 'items': value '[]' must be a non-empty list");
  EXPECT_EQ(error_of("rte: 0.5"), "t.yaml: unknown key 'rte'");
}

TEST(Params, YamlOutReadsBackExactlyWithShortNumbers) {
  Outer o;
  o.rate = 1.0 / 3.0;
  o.gain = 0.85f;
  o.heights_m = {0.1, 0.2 + 0.1};
  o.items.push_back({"w", 5});
  const std::string text = yaml_text(params_to_yaml(o));
  EXPECT_NE(text.find("gain: 0.85\n"), std::string::npos) << text;           // the float's shortest text
  EXPECT_NE(text.find("- 0.1\n"), std::string::npos) << text;                 // not 0.10000000000000001
  EXPECT_NE(text.find("- 0.30000000000000004\n"), std::string::npos) << text;  // as long as exactness needs
  const Outer back = read(text);
  EXPECT_TRUE(same_params(back, o));
  EXPECT_EQ(back.rate, o.rate);
  EXPECT_EQ(back.gain, o.gain);
  EXPECT_EQ(yaml_text(params_to_yaml(back)), text);
  EXPECT_EQ(params_detail::shortest(0.015), "0.015");
  EXPECT_EQ(params_detail::shortest(-0.1f), "-0.1");
  EXPECT_EQ(params_detail::shortest(9.21f), "9.21");
  // Whole and large numbers in plain decimals, not %g's exponent ("3e+01"); tiny and huge ones keep it.
  EXPECT_EQ(params_detail::shortest(30.0), "30");
  EXPECT_EQ(params_detail::shortest(150.0), "150");
  EXPECT_EQ(params_detail::shortest(-30.0), "-30");
  EXPECT_EQ(params_detail::shortest(480.0f), "480");
  EXPECT_EQ(params_detail::shortest(1200.5), "1200.5");
  EXPECT_EQ(params_detail::shortest(1e-5), "1e-05");
  EXPECT_EQ(params_detail::shortest(1e20), "1e+20");
  for (const double v : {30.0, 1e6, 123456789.0, 0.1, 1.0 / 3.0, 2.5e14})
    EXPECT_EQ(std::strtod(params_detail::shortest(v).c_str(), nullptr), v) << v;
}

TEST(Params, ValidateChecksStructsBuiltInCode) {
  Outer o;
  EXPECT_NO_THROW(validate_params(o, "test"));
  o.inner.low_m = -1.0;
  try {
    validate_params(o, "test");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "test: inner.low_m = -1 must be > 0");
  }
  o = Outer{};
  o.planner = "z";
  EXPECT_THROW(validate_params(o, "test"), InputError);
  o = Outer{};
  o.items[0].name.clear();
  EXPECT_THROW(validate_params(o, "test"), InputError);
}

TEST(Params, DescribeListsEveryKeyWithItsLimitsAndHelp) {
  const std::vector<ParamDescription> d = describe_params(Outer{}, "outer");
  ASSERT_EQ(d.size(), 11u);
  EXPECT_EQ(d[0].key, "outer.rate");
  EXPECT_EQ(d[0].value, "0.25");
  EXPECT_EQ(d[0].limits, "must be in [0, 1]");
  EXPECT_EQ(d[0].help, "A probability");
  EXPECT_EQ(d[6].key, "outer.mode");
  EXPECT_EQ(d[6].limits, "one of: fast, slow");
  EXPECT_EQ(d[8].key, "outer.inner.low_m");
  EXPECT_EQ(d[10].key, "outer.items");
}

TEST(Params, SectionsMayBeComponentFiles) {
  const std::string dir = ::testing::TempDir();
  { std::ofstream(dir + "/inner.yaml") << "low_m: 0.3\nhigh_m: 0.4\n"; }
  { std::ofstream(dir + "/bad_inner.yaml") << "low_m: -3\n"; }
  YamlReader y = YamlReader::load_string("inner: inner.yaml\n", "bundle.yaml");
  Outer o;
  YamlIn in(y, true, dir);
  o.visit(in);
  y.finish();
  EXPECT_EQ(o.inner.low_m, 0.3);
  YamlReader z = YamlReader::load_string("inner: bad_inner.yaml\n", "bundle.yaml");
  YamlIn in2(z, true, dir);
  try {
    o.visit(in2);
    FAIL();
  } catch (const InputError& e) {
    // The component file is named, not the bundle.
    EXPECT_NE(std::string(e.what()).find("bad_inner.yaml: key 'low_m': value '-3' must be > 0"), std::string::npos)
        << e.what();
  }
}

// The commented YAML of the settings files: every key once, with its help as a comment (a
// choice's names too), and it reads back to the same struct.
TEST(Params, YamlDocWritesEveryKeyWithItsHelpAndReadsBack) {
  Outer o;
  o.rate = 0.125;
  o.inner.high_m = 0.75;
  const std::string text = params_yaml_doc(o, "# header\n");
  EXPECT_EQ(text.rfind("# header\nrate: 0.125", 0), 0u) << text;
  EXPECT_NE(text.find("# A probability\n"), std::string::npos) << text;
  EXPECT_NE(text.find("mode: fast"), std::string::npos) << text;
  EXPECT_NE(text.find("# An enum; one of: fast, slow\n"), std::string::npos) << text;
  EXPECT_NE(text.find("# A name from a list; one of: a, b\n"), std::string::npos) << text;
  EXPECT_NE(text.find("inner:"), std::string::npos) << text;
  EXPECT_NE(text.find("\n  high_m: 0.75"), std::string::npos) << text;  // nested two spaces in
  EXPECT_NE(text.find("heights_m: [0.4, 1]"), std::string::npos) << text;
  EXPECT_NE(text.find("items: [{name: x, weight: 2}]"), std::string::npos) << text;
  const Outer back = read(text);
  EXPECT_TRUE(same_params(back, o));
  EXPECT_EQ(back.inner.high_m, 0.75);
}

namespace {
struct Renamed {
  Inner current;
  template <class A>
  void visit(A& a) {
    a.renamed("former", "current");
    a.section("current", current, "A section that had another name");
  }
};
}  // namespace

// A section's former key is still read, as the current one, with one warning naming both; both
// keys at once is an error; the former key is never written.
TEST(Params, AFormerKeyIsReadWithAWarning) {
  std::vector<std::string> warnings;
  const auto previous = set_warning_handler([&](const std::string& w) { warnings.push_back(w); });
  YamlReader y = YamlReader::load_string("former:\n  low_m: 0.2\n", "old.yaml");
  const Renamed r = params_from_yaml<Renamed>(y);
  EXPECT_NO_THROW(y.finish());
  EXPECT_EQ(r.current.low_m, 0.2);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "old.yaml: key 'former' is now 'current'; read as such (rename it: the old name will be refused)");
  YamlReader now = YamlReader::load_string("current:\n  low_m: 0.3\n", "new.yaml");
  EXPECT_EQ(params_from_yaml<Renamed>(now).current.low_m, 0.3);
  EXPECT_EQ(warnings.size(), 1u);  // the current key warns of nothing
  YamlReader both = YamlReader::load_string("former: {}\ncurrent: {}\n", "both.yaml");
  try {
    params_from_yaml<Renamed>(both);
    ADD_FAILURE() << "both keys accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("give 'current' only"), std::string::npos) << e.what();
  }
  const std::string out = yaml_text(params_to_yaml(r));
  EXPECT_EQ(out.find("former"), std::string::npos) << out;
  set_warning_handler(previous);
}
