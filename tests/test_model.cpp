#include <fmt/format.h>
#include <gtest/gtest.h>

#include <string>

#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/io/urdf.hpp"

TEST(Model, LoadsPuma) {
  const auto m = massid::load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  EXPECT_EQ(m.num_joints(), 3);
  EXPECT_EQ(m.num_links(), 5);
}

namespace {

std::string load_error(const std::string& xml) {
  try {
    massid::load_urdf_string(xml, "", "r.urdf");
  } catch (const massid::InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(Model, LinkThatIsTheChildOfTwoJointsIsRefused) {
  // Regression (found by fuzz_urdf): urdfdom accepts it, and link c (mass 1 kg)
  // was measured twice.
  EXPECT_EQ(load_error("<robot name=\"r\">\n<link name=\"a\"/><link name=\"b\"/>\n"
                       "<link name=\"c\"><inertial><mass value=\"1\"/></inertial></link>\n"
                       "<joint name=\"j1\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/>"
                       "</joint>\n"
                       "<joint name=\"j2\" type=\"fixed\"><parent link=\"a\"/><child link=\"c\"/>"
                       "</joint>\n"
                       "<joint name=\"j3\" type=\"fixed\"><parent link=\"b\"/><child link=\"c\"/>"
                       "</joint>\n</robot>"),
            "r.urdf:6: link 'c' is the child of two joints, 'j2' (line 5) and 'j3'; a URDF is a "
            "tree");
}

TEST(Model, LoopOfJointsIsRefused) {
  // Regression (found by fuzz_urdf, LeakSanitizer): urdfdom accepts a loop cut
  // off from the root; its links (and their masses) vanished from the model and
  // urdfdom leaked them.
  EXPECT_EQ(load_error("<robot name=\"r\">\n<link name=\"a\"/>\n"
                       "<link name=\"b\"><inertial><mass value=\"1\"/></inertial></link>\n"
                       "<link name=\"c\"><inertial><mass value=\"1\"/></inertial></link>\n"
                       "<joint name=\"j2\" type=\"fixed\"><parent link=\"b\"/><child link=\"c\"/>"
                       "</joint>\n"
                       "<joint name=\"j3\" type=\"fixed\"><parent link=\"c\"/><child link=\"b\"/>"
                       "</joint>\n</robot>"),
            "r.urdf:6: joint 'j3' closes a loop: link 'b' is its own ancestor; a URDF is a tree");
  EXPECT_EQ(load_error("<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n"
                       "<joint name=\"j\" type=\"fixed\"><parent link=\"b\"/><child link=\"b\"/>"
                       "</joint>\n</robot>"),
            "r.urdf:4: joint 'j' closes a loop: link 'b' is its own ancestor; a URDF is a tree");
}

TEST(Model, NamesMustBeUtf8) {
  // Regression (found by fuzz_urdf): a name with a Latin-1 byte loaded, and
  // writing the params file (JSON) then threw nlohmann's type_error 316.
  EXPECT_EQ(load_error("<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\xFA\"/>\n"
                       "<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/>"
                       "<child link=\"b\xFA\"/><axis xyz=\"0 0 1\"/></joint>\n</robot>"),
            "r.urdf:3: link name 'b\\xFA' is not UTF-8 text");
  EXPECT_EQ(load_error("<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n"
                       "<joint name=\"j\xC3\" type=\"continuous\"><parent link=\"a\"/>"
                       "<child link=\"b\"/><axis xyz=\"0 0 1\"/></joint>\n</robot>"),
            "r.urdf:4: joint name 'j\\xC3' is not UTF-8 text");
  // Not UTF-8 either: an overlong form, a surrogate, a code point beyond
  // U+10FFFF, a sequence cut short.
  for (const std::string bad : {"\xC0\xAF", "\xE0\x80\xAF", "\xED\xA0\x80", "\xF4\x90\x80\x80",
                                "\xE2\x82", "\xF0\x9F\xA4"}) {
    std::string shown;
    for (const char ch : bad) shown += fmt::format("\\x{:02X}", static_cast<unsigned char>(ch));
    EXPECT_EQ(load_error("<robot name=\"r\">\n<link name=\"a" + bad + "\"/>\n</robot>"),
              "r.urdf:2: link name 'a" + shown + "' is not UTF-8 text");
  }
  // Multi-byte UTF-8 is fine (the largest code point, U+10FFFF, too).
  EXPECT_EQ(load_error("<robot name=\"r\"><link name=\"\xC3\xA9l\xE2\x82\xAC\xF0\x9F\xA4\x96\"/>"
                       "</robot>"),
            "no error");
  EXPECT_EQ(load_error("<robot name=\"r\"><link name=\"a\xF4\x8F\xBF\xBF\"/></robot>"), "no error");
}
