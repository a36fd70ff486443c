// file_stem_for_id: the one rule for file names made from ids (core/io/file_names.h).
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "core/io/file_names.h"

using c3d::file_stem_for_id;

TEST(FileNames, PlainIdsAreKeptAsTheyAre) {
  for (const char* id : {"10280503000001", "32.73.01", "P-1_b", "a_b"}) EXPECT_EQ(file_stem_for_id(id), id);
}

TEST(FileNames, NoIdLeavesTheFolderOrHidesOrLooksLikeAnOption) {
  for (const std::string& id : std::vector<std::string>{"../../../x", "/etc/passwd", "a/b", "..", ".", "", ".hidden", "-rf", "a\\b",
                               std::string("nul\0byte", 8), "C:\\x", "\xff\xfe"}) {
    const std::string s = file_stem_for_id(id);
    EXPECT_EQ(s.find('/'), std::string::npos) << s;
    EXPECT_EQ(s.find('\\'), std::string::npos) << s;
    EXPECT_EQ(s.find('\0'), std::string::npos) << s;
    ASSERT_FALSE(s.empty());
    EXPECT_NE(s[0], '.') << s;
    EXPECT_NE(s[0], '-') << s;
    EXPECT_LE(s.size(), 80u);
  }
}

TEST(FileNames, DifferentIdsNeverShareAName) {
  const std::vector<std::string> ids = {"a/b", "a_b", "a:b", "a b", "a\\b", "a_b~0000000000000000",
                                        std::string(200, 'x'), std::string(201, 'x'), "A_B"};
  std::set<std::string> names;
  for (const auto& id : ids) names.insert(file_stem_for_id(id));
  EXPECT_EQ(names.size(), ids.size());
  EXPECT_EQ(file_stem_for_id("a/b"), file_stem_for_id("a/b")) << "the same id, the same name, every run";
}
