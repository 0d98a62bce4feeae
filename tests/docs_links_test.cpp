// Every relative link and image in README.md and docs/**/*.md names a file in the repository, every
// #anchor into a page names one of its headings, and no page names a path outside it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#ifndef EITBENCH_SOURCE_DIR
#error "EITBENCH_SOURCE_DIR must name the repository root"
#endif

namespace fs = std::filesystem;

namespace {

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

// The page's lines outside fenced code blocks.
std::vector<std::string> prose_lines(const std::string& text) {
  static const std::regex fence(R"(^\s*```)");
  std::vector<std::string> out;
  std::istringstream lines(text);
  std::string line;
  bool in_fence = false;
  while (std::getline(lines, line)) {
    if (std::regex_search(line, fence)) {
      in_fence = !in_fence;
      continue;
    }
    if (!in_fence) out.push_back(line);
  }
  return out;
}

// The targets of the page's inline links and images, [text](target) and ![alt](target), and of
// its reference definitions, [x]: target. Code blocks and code spans hold no links.
std::vector<std::string> link_targets(const std::string& text) {
  static const std::regex code_span("`[^`]*`");
  static const std::regex reference(R"(^ {0,3}\[[^\]]+\]:\s*<?([^\s>]+))");
  static const std::regex inline_link(R"(\[[^\]]*\]\(\s*<?([^)\s>]*)>?(\s+"[^"]*")?\s*\))");
  std::vector<std::string> targets;
  std::string prose;
  for (std::string line : prose_lines(text)) {
    line = std::regex_replace(line, code_span, "``");
    std::smatch m;
    if (std::regex_search(line, m, reference)) targets.push_back(m[1]);
    prose += line + "\n";
  }
  for (std::sregex_iterator it(prose.begin(), prose.end(), inline_link), end; it != end; ++it)
    targets.push_back((*it)[1]);
  return targets;
}

// A code point of Latin-1's punctuation and signs, × or ÷, general punctuation, the signs among
// the super- and subscripts, currency, arrows, mathematical or other symbols: characters GitHub
// drops from a heading's anchor, where it keeps letters, marks, digits and the connectors.
bool dropped_from_anchors(char32_t c) {
  const bool latin1_sign = c >= 0xA0 && c <= 0xBF && c != 0xAA && c != 0xB2 && c != 0xB3 &&
                           c != 0xB5 && c != 0xB9 && c != 0xBA && (c < 0xBC || c > 0xBE);
  const bool script_sign = (c >= 0x207A && c <= 0x207E) || (c >= 0x208A && c <= 0x208E);
  return latin1_sign || c == 0xD7 || c == 0xF7 || (c >= 0x2000 && c <= 0x206F) || script_sign ||
         (c >= 0x20A0 && c <= 0x20CF) || (c >= 0x2190 && c <= 0x2BFF);
}

// GitHub's anchor of a heading: its text without link targets, emphasis and code marks, in lower
// case, with what is neither a letter, a digit, a space, '-' nor '_' dropped and spaces made '-'.
std::string github_anchor(std::string heading) {
  static const std::regex link(R"(!?\[([^\]]*)\]\([^)]*\))");
  heading = std::regex_replace(heading, link, "$1");
  std::string out;
  for (std::size_t i = 0; i < heading.size();) {
    const auto byte = static_cast<unsigned char>(heading[i]);
    if (byte < 0x80) {
      const char c = static_cast<char>(std::tolower(byte));
      if (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') out += c;
      if (c == ' ') out += '-';
      ++i;
      continue;
    }
    const std::size_t length = byte >= 0xF0 ? 4 : byte >= 0xE0 ? 3 : 2;
    char32_t c = byte & (length == 2 ? 0x1F : length == 3 ? 0x0F : 0x07);
    for (std::size_t k = 1; k < length && i + k < heading.size(); ++k)
      c = (c << 6) | (static_cast<unsigned char>(heading[i + k]) & 0x3F);
    if (!dropped_from_anchors(c)) out += heading.substr(i, length);
    i += length;
  }
  return out;
}

// The anchors of a page's ATX headings (# to ######), a repeated one numbered -1, -2, ... as
// GitHub numbers them.
std::set<std::string> heading_anchors(const std::string& text) {
  static const std::regex heading(R"(^ {0,3}#{1,6}[ \t]+(.*?)[ \t]*#*[ \t]*$)");
  std::set<std::string> anchors;
  std::map<std::string, int> seen;
  for (const std::string& line : prose_lines(text)) {
    std::smatch m;
    if (!std::regex_match(line, m, heading)) continue;
    const std::string anchor = github_anchor(m[1]);
    const int n = seen[anchor]++;
    anchors.insert(n == 0 ? anchor : anchor + "-" + std::to_string(n));
  }
  return anchors;
}

// The file's bytes, or nothing when it cannot be read.
std::optional<std::string> read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  return std::string{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// True when `path` is `root` or lies below it (both absolute and normalised).
bool inside(const fs::path& path, const fs::path& root) {
  const fs::path relative = path.lexically_relative(root);
  return !relative.empty() && *relative.begin() != "..";
}

// One message for each link that names no file, is absolute or leaves `root`, and for each page
// that names "../shared" or "/work/" anywhere in its text.
std::vector<std::string> link_problems(const fs::path& root,
                                       const std::vector<fs::path>& markdown_files) {
  const fs::path top = fs::weakly_canonical(root);
  std::vector<std::string> problems;
  std::map<fs::path, std::set<std::string>> anchors;  // each page's headings, parsed once
  auto anchors_of = [&](const fs::path& page) -> const std::set<std::string>& {
    auto it = anchors.find(page);
    if (it == anchors.end())
      it = anchors.emplace(page, heading_anchors(read_text(page).value_or(""))).first;
    return it->second;
  };
  for (const fs::path& page : markdown_files) {
    const std::optional<std::string> read = read_text(page);
    const std::string text = read.value_or("");
    const std::string name = fs::weakly_canonical(page).lexically_relative(top).generic_string();
    if (!read) problems.push_back(name + ": cannot be read");
    for (const char* outside : {"../shared", "/work/"})
      if (text.find(outside) != std::string::npos)
        problems.push_back(name + ": names \"" + outside + "\", a path outside the repository");
    for (const std::string& target : link_targets(text)) {
      if (target.empty() || starts_with(target, "http://") || starts_with(target, "https://") ||
          starts_with(target, "mailto:"))
        continue;
      const std::size_t hash = target.find('#');
      const std::string anchor = hash == std::string::npos ? "" : target.substr(hash + 1);
      const std::string where = name + ": link " + target;
      if (hash == 0) {
        if (!anchors_of(fs::weakly_canonical(page)).count(anchor))
          problems.push_back(where + " names no heading");
        continue;
      }
      const fs::path file = target.substr(0, hash);
      if (file.is_absolute() || file.has_root_name() || file.has_root_directory()) {
        problems.push_back(where + " is an absolute path");
        continue;
      }
      const fs::path resolved = fs::weakly_canonical(page.parent_path() / file);
      if (!inside(resolved, top))
        problems.push_back(where + " leaves the repository");
      else if (!fs::exists(resolved))
        problems.push_back(where + " names no file");
      else if (!anchor.empty() && resolved.extension() == ".md" &&
               !anchors_of(resolved).count(anchor))
        problems.push_back(where + " names no heading");
    }
  }
  return problems;
}

}  // namespace

TEST(DocsLinks, EveryLinkInTheReadmeAndTheDocsNamesAFileInTheRepository) {
  const fs::path root = EITBENCH_SOURCE_DIR;
  std::vector<fs::path> pages;
  ASSERT_TRUE(fs::is_directory(root / "docs")) << root / "docs";
  for (const auto& entry : fs::recursive_directory_iterator(root / "docs"))
    if (entry.is_regular_file() && entry.path().extension() == ".md") pages.push_back(entry.path());
  std::sort(pages.begin(), pages.end());
  pages.insert(pages.begin(), root / "README.md");
  for (const std::string& problem : link_problems(root, pages)) ADD_FAILURE() << problem;
}

TEST(DocsLinks, TheCheckerReportsABrokenLinkAMissingHeadingAndALinkOutOfTheRepository) {
  const fs::path root =
      fs::temp_directory_path() / ("docs_links_test_" + std::to_string(std::random_device{}()));
  fs::create_directories(root / "docs");
  std::ofstream(root / "README.md") << "# Top\n## The run: `run`, `report`\n## Twice\n## Twice\n";
  std::ofstream(root / "docs" / "page.md")
      << "# Page\nA [broken link](missing.md), a [good one](../README.md#top), [code in a\n"
         "heading](../README.md#the-run-run-report), [the second of two](../README.md#twice-1), "
         "[a\n"
         "missing heading](../README.md#nowhere), an ![image out of the\n"
         "repository](../../outside.png), [the web](https://example.org), [an anchor](#page) and\n"
         "[a wrong one](#top).\n"
         "```sh\n[not a link](nowhere.md)\n# not a heading\n```\n[in a fence](#not-a-heading)\n";
  const std::vector<std::string> problems = link_problems(root, {root / "docs" / "page.md"});
  fs::remove_all(root);
  ASSERT_EQ(problems.size(), 5u) << ::testing::PrintToString(problems);
  EXPECT_NE(problems[0].find("missing.md names no file"), std::string::npos) << problems[0];
  EXPECT_NE(problems[1].find("../README.md#nowhere names no heading"), std::string::npos)
      << problems[1];
  EXPECT_NE(problems[2].find("../../outside.png leaves the repository"), std::string::npos)
      << problems[2];
  EXPECT_NE(problems[3].find("#top names no heading"), std::string::npos) << problems[3];
  EXPECT_NE(problems[4].find("#not-a-heading names no heading"), std::string::npos) << problems[4];
}

// GitHub keeps letters and digits of any script and drops punctuation and symbols.
TEST(DocsLinks, AnAnchorKeepsLettersAndDigitsAndDropsSigns) {
  EXPECT_EQ(github_anchor("Speed \u2013 2\u00d7 faster: D\u2081\u2086, caf\u00e9 [here](x.md)"),
            "speed--2-faster-d\u2081\u2086-caf\u00e9-here");
  EXPECT_EQ(github_anchor("The benchmark: `run`, `report`, `compare`, `history`"),
            "the-benchmark-run-report-compare-history");
}
