#include "massid/identify/urdf_inertials.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <map>
#include <optional>
#include <tuple>

#include "io/atomic_file.hpp"
#include "massid/core/errors.hpp"

namespace massid {

namespace {

// The XML the edit needs to know, found by a scanner that follows comments,
// CDATA, processing instructions, DOCTYPE and quoted attribute values: the
// <link> children of <robot>, their byte spans and those of their direct
// <inertial> child. (No XML library reports byte offsets; tinyxml2, which
// load_urdf uses, reports lines only.)
struct LinkSpan {
  size_t start = 0;          // '<' of <link
  size_t start_tag_end = 0;  // one past '>' of the start tag
  bool self_closing = false;
  size_t end_tag = 0;  // '<' of </link> (self-closing: the '/' of "/>")
  std::optional<std::pair<size_t, size_t>>
      inertial;  // [start, end) of <inertial ...>...</inertial>
};

std::string decode_entities(std::string s) {
  static const std::pair<const char*, char> kEntities[] = {
      {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}, {"&amp;", '&'}};
  for (const auto& [entity, c] : kEntities)
    for (size_t at = s.find(entity); at != std::string::npos; at = s.find(entity, at + 1))
      s.replace(at, std::string(entity).size(), 1, c);
  return s;
}

class Scanner {
 public:
  Scanner(const std::string& text, const std::string& source) : text_(text), source_(source) {}

  std::map<std::string, LinkSpan> links() {
    std::map<std::string, LinkSpan> out;
    std::vector<std::string> open;  // element names from the root
    std::string link_name;          // the <link> being read (depth 2)
    LinkSpan link;
    size_t at = 0;
    while ((at = text_.find('<', at)) != std::string::npos) {
      if (starts(at, "<!--")) {
        at = past(at, "-->");
      } else if (starts(at, "<![CDATA[")) {
        at = past(at, "]]>");
      } else if (starts(at, "<?")) {
        at = past(at, "?>");
      } else if (starts(at, "<!")) {
        at = past_doctype(at);
      } else if (starts(at, "</")) {
        const size_t close = past(at, ">");
        const std::string name = trim(text_.substr(at + 2, close - 1 - (at + 2)));
        if (open.empty() || open.back() != name)
          fail(at, "an end tag </" + name + "> out of place");
        open.pop_back();
        if (name == "link" && open.size() == 1) {
          link.end_tag = at;
          add(out, link_name, link, at);
        }
        at = close;
      } else {
        const Tag tag = read_tag(at);
        if (open.size() == 1 && tag.name == "link") {
          link = LinkSpan{};
          link.start = at;
          link.start_tag_end = tag.end;
          link.self_closing = tag.self_closing;
          link_name = tag.name_attribute;
          if (tag.self_closing) {
            link.end_tag = tag.end - 2;
            add(out, link_name, link, at);
          }
        } else if (open.size() == 2 && open[1] == "link" && tag.name == "inertial") {
          link.inertial = {at, tag.end};
          if (!tag.self_closing) inertial_depth_ = 3;
        }
        if (!tag.self_closing) open.push_back(tag.name);
        at = tag.end;
      }
      // An <inertial> element ends with its end tag at depth 3.
      if (inertial_depth_ && open.size() == 2 && link.inertial) {
        link.inertial->second = at;
        inertial_depth_ = 0;
      }
    }
    if (!open.empty()) fail(text_.size(), "<" + open.back() + "> is not closed");
    return out;
  }

 private:
  struct Tag {
    std::string name, name_attribute;
    size_t end = 0;  // one past '>'
    bool self_closing = false;
  };

  bool starts(size_t at, const char* s) const { return text_.compare(at, strlen(s), s) == 0; }

  size_t past(size_t at, const char* end) const {
    const size_t e = text_.find(end, at);
    if (e == std::string::npos) fail(at, fmt::format("no closing '{}'", end));
    return e + strlen(end);
  }

  size_t past_doctype(size_t at) const {
    int brackets = 0;
    for (size_t i = at + 2; i < text_.size(); ++i) {
      if (text_[i] == '[') ++brackets;
      if (text_[i] == ']') --brackets;
      if (text_[i] == '>' && brackets == 0) return i + 1;
    }
    fail(at, "a <!DOCTYPE without its end");
  }

  Tag read_tag(size_t at) const {
    Tag tag;
    size_t i = at + 1;
    while (i < text_.size() && !std::isspace(static_cast<unsigned char>(text_[i])) &&
           text_[i] != '>' && text_[i] != '/')
      tag.name += text_[i++];
    while (i < text_.size() && text_[i] != '>') {
      if (text_[i] == '"' || text_[i] == '\'') {
        const size_t close = text_.find(text_[i], i + 1);
        if (close == std::string::npos) fail(i, "an attribute value without its closing quote");
        // name="value": the attribute's name precedes '=' before the quote.
        size_t eq = i;
        while (eq > at && std::isspace(static_cast<unsigned char>(text_[eq - 1]))) --eq;
        if (eq > at && text_[eq - 1] == '=') {
          size_t name_end = eq - 1;
          while (name_end > at && std::isspace(static_cast<unsigned char>(text_[name_end - 1])))
            --name_end;
          size_t name_start = name_end;
          while (name_start > at &&
                 !std::isspace(static_cast<unsigned char>(text_[name_start - 1])))
            --name_start;
          if (text_.compare(name_start, name_end - name_start, "name") == 0)
            tag.name_attribute = decode_entities(text_.substr(i + 1, close - i - 1));
        }
        i = close + 1;
      } else {
        ++i;
      }
    }
    if (i >= text_.size()) fail(at, "a tag without its '>'");
    tag.self_closing = text_[i - 1] == '/';
    tag.end = i + 1;
    if (tag.name.empty()) fail(at, "a tag without a name");
    return tag;
  }

  void add(std::map<std::string, LinkSpan>& out, const std::string& name, const LinkSpan& span,
           size_t at) const {
    if (!out.emplace(name, span).second) fail(at, "link '" + name + "' is defined twice");
  }

  static std::string trim(const std::string& s) {
    const size_t b = s.find_first_not_of(" \t\r\n"), e = s.find_last_not_of(" \t\r\n");
    return b == std::string::npos ? "" : s.substr(b, e - b + 1);
  }

  [[noreturn]] void fail(size_t at, const std::string& what) const {
    const size_t upto = std::min(at, text_.size());
    const size_t line = 1 + std::count(text_.begin(), text_.begin() + upto, '\n');
    const size_t line_start = text_.rfind('\n', upto == 0 ? 0 : upto - 1);
    const size_t column = upto - (line_start == std::string::npos ? 0 : line_start + 1) + 1;
    throw InputError(
        fmt::format("{}:{}:{}: cannot edit the inertials: {}", source_, line, column, what));
  }

  const std::string& text_;
  const std::string& source_;
  int inertial_depth_ = 0;
};

// The whitespace that precedes position `at` on its line, when only whitespace does.
std::optional<std::string> line_indent(const std::string& text, size_t at) {
  size_t b = at;
  while (b > 0 && (text[b - 1] == ' ' || text[b - 1] == '\t')) --b;
  if (b > 0 && text[b - 1] != '\n') return std::nullopt;
  return text.substr(b, at - b);
}

std::string number(double v) { return fmt::format("{}", v == 0.0 ? 0.0 : v); }

// <inertial>...</inertial>; the first line without indentation (it takes the
// place of the old element or follows the caller's indentation).
std::string inertial_element(const LinkInertial& e, const std::string& indent,
                             const std::string& step, const std::string& newline) {
  const std::string in = indent + step;
  std::string s = "<inertial>" + newline;
  if (!e.note.empty()) {  // "--" may not appear inside an XML comment
    std::string note = e.note;
    for (size_t at = note.find("--"); at != std::string::npos; at = note.find("--", at))
      note.replace(at, 2, "- -");
    s += in + "<!-- " + note + " -->" + newline;
  }
  s += fmt::format("{}<origin xyz=\"{} {} {}\" rpy=\"0 0 0\"/>{}", in, number(e.com.x()),
                   number(e.com.y()), number(e.com.z()), newline);
  s += fmt::format("{}<mass value=\"{}\"/>{}", in, number(e.mass), newline);
  const Eigen::Matrix3d& I = e.inertia;
  s += fmt::format(
      "{}<inertia ixx=\"{}\" ixy=\"{}\" ixz=\"{}\" iyy=\"{}\" iyz=\"{}\" izz=\"{}\"/>{}", in,
      number(I(0, 0)), number(0.5 * (I(0, 1) + I(1, 0))), number(0.5 * (I(0, 2) + I(2, 0))),
      number(I(1, 1)), number(0.5 * (I(1, 2) + I(2, 1))), number(I(2, 2)), newline);
  return s + indent + "</inertial>";
}

}  // namespace

std::string replace_inertials(const std::string& urdf, const std::string& source,
                              const std::vector<LinkInertial>& edits) {
  const std::map<std::string, LinkSpan> links = Scanner(urdf, source).links();
  const std::string newline = urdf.find("\r\n") != std::string::npos ? "\r\n" : "\n";
  // The file's indentation step: that of the first <link> (else two spaces).
  std::string step = "  ";
  if (!links.empty()) {
    const LinkSpan& first =
        std::min_element(links.begin(), links.end(), [](const auto& a, const auto& b) {
          return a.second.start < b.second.start;
        })->second;
    if (const auto indent = line_indent(urdf, first.start); indent && !indent->empty())
      step = *indent;
  }
  // Replacements [start, end) -> text, applied from the end of the file.
  std::vector<std::tuple<size_t, size_t, std::string>> cuts;
  std::map<std::string, int> seen;
  for (const LinkInertial& e : edits) {
    if (seen[e.link]++)
      throw InputError(fmt::format("{}: link '{}' is given two inertials", source, e.link));
    const auto it = links.find(e.link);
    if (it == links.end())
      throw InputError(fmt::format("{}: no link '{}' to write the inertial of", source, e.link));
    const LinkSpan& span = it->second;
    const std::string link_indent = line_indent(urdf, span.start).value_or("");
    if (span.inertial) {
      const auto [b, end] = *span.inertial;
      const std::string indent = line_indent(urdf, b).value_or(link_indent + step);
      cuts.emplace_back(b, end, inertial_element(e, indent, step, newline));
    } else if (span.self_closing) {  // <link name="x"/> -> <link name="x"> ... </link>
      const std::string indent = link_indent + step;
      cuts.emplace_back(span.end_tag, span.start_tag_end,
                        ">" + newline + indent + inertial_element(e, indent, step, newline) +
                            newline + link_indent + "</link>");
    } else if (const auto indent = line_indent(urdf, span.end_tag)) {  // </link> on its own line
      const size_t line_start = span.end_tag - indent->size();
      const std::string child = *indent + step;
      cuts.emplace_back(line_start, line_start,
                        child + inertial_element(e, child, step, newline) + newline);
    } else {
      cuts.emplace_back(span.end_tag, span.end_tag, inertial_element(e, "", "", ""));
    }
  }
  std::sort(cuts.begin(), cuts.end(),
            [](const auto& a, const auto& b) { return std::get<0>(a) > std::get<0>(b); });
  std::string out = urdf;
  for (const auto& [b, e, text] : cuts) out.replace(b, e - b, text);
  return out;
}

std::string identified_urdf(const Model& model, const PhysicalSummary& physical,
                            const std::string& note) {
  const std::string text = read_file(model.source, "cannot read the URDF");
  if (static_cast<int>(physical.links.size()) != model.num_links())
    throw InputError(fmt::format("{}: the physical parameters are of another model", model.source));
  std::vector<LinkInertial> edits;
  for (int i = 0; i < model.num_links(); ++i) {
    const PhysicalLink& l = physical.links[i];
    // The root link without an <inertial> gets none (a root body is no part of
    // a robot's dynamics; KDL warns about one); a massless frame the data
    // cannot see (ee_link, tool0) stays massless.
    const bool root = model.links[i].name == model.root_link;
    if ((root && !model.links[i].has_inertial) || l.unseen) continue;
    edits.push_back(LinkInertial{model.links[i].name, l.mass, l.com, l.inertia_com,
                                 l.prior_body ? note + "; no mass in the original URDF: the "
                                                       "fit's small body"
                                              : note});
  }
  return replace_inertials(text, model.source, edits);
}

}  // namespace massid
