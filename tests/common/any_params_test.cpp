// A parameter struct held by type at run time (common/any_params.h): visited by every archive
// as the struct itself, copied deeply, read back by its type only.

#include <gtest/gtest.h>

#include "canopy/common/any_params.h"

using namespace canopy;

namespace {

struct Small {
  double radius_m = 0.4;
  int count = 3;
  template <class A>
  void visit(A& a) {
    a("radius_m", radius_m, limits::positive(), "Radius [m]");
    a("count", count, limits::in(1, 10), "Count");
  }
};

struct Other {
  bool on = true;
  template <class A>
  void visit(A& a) {
    a("on", on, "Switch");
  }
};

// A struct with an AnyParams section, as the nbv settings hold the planners' sections.
struct Holder {
  AnyParams small{Small{}};
  template <class A>
  void visit(A& a) {
    a.section("small", small, "The small struct");
  }
};

}  // namespace

TEST(AnyParams, HoldsOneTypeAndCopiesDeeply) {
  AnyParams a(Small{});
  EXPECT_FALSE(a.empty());
  EXPECT_TRUE(a.holds<Small>());
  EXPECT_FALSE(a.holds<Other>());
  EXPECT_EQ(a.get<Other>(), nullptr);
  ASSERT_NE(a.get<Small>(), nullptr);
  a.get<Small>()->count = 7;
  AnyParams b = a;
  b.get<Small>()->count = 9;
  EXPECT_EQ(a.get<Small>()->count, 7);  // a copy, not a shared struct
  EXPECT_EQ(b.get<Small>()->count, 9);
  a = b;
  EXPECT_EQ(a.get<Small>()->count, 9);
  EXPECT_TRUE(AnyParams().empty());
}

TEST(AnyParams, IsVisitedAsTheStructItHolds) {
  Holder h;
  h.small.get<Small>()->radius_m = 0.25;
  // YAML out and in.
  const std::string text = yaml_text(params_to_yaml(h));
  EXPECT_EQ(text, "small:\n  radius_m: 0.25\n  count: 3\n");
  YamlReader y = YamlReader::load_string("small:\n  count: 5\n", "t.yaml");
  Holder back = params_from_yaml<Holder>(y);
  y.finish();
  EXPECT_EQ(back.small.get<Small>()->count, 5);
  EXPECT_EQ(back.small.get<Small>()->radius_m, 0.4);
  YamlReader bad = YamlReader::load_string("small:\n  count: 50\n", "t.yaml");
  EXPECT_THROW(params_from_yaml<Holder>(bad), InputError);
  // JSON, validation, descriptions and the commented YAML.
  EXPECT_EQ(params_to_json(h).dump(), R"({"small":{"count":3,"radius_m":0.25}})");
  h.small.get<Small>()->count = 0;
  try {
    validate_params(h, "test");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "test: small.count = 0 must be in [1, 10]");
  }
  const std::vector<ParamDescription> d = describe_params(Holder{});
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0].key, "small.radius_m");
  EXPECT_EQ(d[1].help, "Count");
  EXPECT_NE(params_yaml_doc(Holder{}).find("small:                        # The small struct\n  radius_m: 0.4"),
            std::string::npos)
      << params_yaml_doc(Holder{});
}
