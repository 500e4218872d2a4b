// Strict YAML reading: unknown keys and wrong types named, alias bombs, empty and repeated keys (common/yaml_reader.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/read_file.h"
#include "canopy/common/yaml_reader.h"

namespace canopy {
namespace {

TEST(YamlReader, UnknownKeysAndTypesAreNamed) {
  YamlReader y = YamlReader::load_string("a: 1\nb: two\nc: {d: 3}\n", "t.yaml");
  EXPECT_EQ(y.get("a", 0), 1);
  try {
    y.require<double>("b");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.yaml: key 'b': value 'two'"), std::string::npos) << e.what();
  }
  YamlReader c = y.child("c");
  EXPECT_THROW(c.finish(), InputError);  // d not read
  EXPECT_EQ(c.get("d", 0), 3);
  EXPECT_NO_THROW(c.finish());
  EXPECT_NO_THROW(y.finish());
  YamlReader z = YamlReader::load_string("a: 1\nzz: 2\n", "t.yaml");
  z.get("a", 0);
  try {
    z.finish();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'zz'"), std::string::npos);
  }
  EXPECT_THROW(YamlReader::load_string("a: [1, 2\n", "bad.yaml"), InputError);
  EXPECT_THROW(YamlReader::load_file("/nonexistent.yaml"), InputError);
}

// Nested aliases that expand to billions of nodes are refused while parsing, in linear time.
TEST(YamlReader, AliasBombsAndEmptyFilesAreRefused) {
  std::string bomb = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i <= 9; ++i) {
    bomb += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k) bomb += std::string(k ? ", " : "") + "*a" + std::to_string(i - 1);
    bomb += "]\n";
  }
  try {
    YamlReader::load_string(bomb, "bomb.yaml");
    FAIL() << "an alias bomb was parsed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("expands to more than"), std::string::npos) << e.what();
  }
  // A few aliases are fine.
  EXPECT_NO_THROW(YamlReader::load_string("base: &b {x: 1}\none: *b\ntwo: *b\n", "ok.yaml"));
  const std::string empty = testing::TempDir() + "/empty.yaml";
  write_file_atomic(empty, "  \n");
  EXPECT_THROW(YamlReader::load_file(empty), InputError);
  EXPECT_THROW(YamlReader::load_file("/dev/zero"), InputError);
  // A bad block list is named on one line.
  YamlReader y = YamlReader::load_string("fruits:\n  - 1\n  - .nan\n", "w.yaml");
  try {
    y.fail("fruits", "must be finite");
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[1, .nan]"), std::string::npos) << e.what();
  }
}

// Named choices: the table's names parse, an absent key gives the fallback, anything else
// fails naming the file, key, value and the valid names.
enum class Fruit { kPepper, kTomato };
constexpr EnumName<Fruit> kFruitNames[] = {{Fruit::kPepper, "pepper"}, {Fruit::kTomato, "tomato"}};

TEST(YamlReader, ChoicesFromANameTable) {
  YamlReader y = YamlReader::load_string("a: tomato\nb: apple\n", "t.yaml");
  EXPECT_EQ(y.get_choice("a", Fruit::kPepper, kFruitNames), Fruit::kTomato);
  EXPECT_EQ(y.get_choice("missing", Fruit::kTomato, kFruitNames), Fruit::kTomato);
  try {
    y.get_choice("b", Fruit::kPepper, kFruitNames);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.yaml: key 'b': value 'apple' must be one of: pepper, tomato"),
              std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(y.finish());  // every key read
  EXPECT_STREQ(enum_name(kFruitNames, Fruit::kTomato), "tomato");
  EXPECT_EQ(enum_from_name(kFruitNames, "pepper", "--fruit", "fruit"), Fruit::kPepper);
  try {
    enum_from_name(kFruitNames, "kiwi", "--fruit", "fruit");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--fruit: unknown fruit 'kiwi' (valid: pepper, tomato)");
  }
}

TEST(YamlReader, RepeatedKeysAreErrorsNamingBothLines) {
  auto message = [](const std::string& text) {
    try {
      YamlReader::load_string(text, "w.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("seed: 1\nname: a\nseed: 2\n"), "w.yaml: duplicate key 'seed' at lines 1 and 3");
  EXPECT_EQ(message("rows:\n  rows: 2\n  plants_per_row: 3\n  rows: 1\n"),
            "w.yaml: duplicate key 'rows' at lines 2 and 4");
  EXPECT_EQ(message("a: [{x: 1, x: 2}]\n"), "w.yaml: duplicate key 'x' at lines 1 and 1");
  EXPECT_EQ(message("a: {x: 1}\nb: {x: 2}\n"), "no error");  // same key in two mappings is fine
}

TEST(YamlReader, AFolderIsNotAnEmptyFile) {
  try {
    YamlReader::load_file(testing::TempDir());
    FAIL() << "a folder loaded as a YAML file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_file(testing::TempDir()), InputError);
}

}  // namespace
}  // namespace canopy
