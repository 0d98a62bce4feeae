// Every relative link and image in README.md and docs/**/*.md names a file in the repository, and
// no page names a path outside it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <regex>
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

// The targets of the page's inline links and images, [text](target) and ![alt](target), and of
// its reference definitions, [x]: target. Code blocks and code spans hold no links.
std::vector<std::string> link_targets(const std::string& text) {
  static const std::regex fence(R"(^\s*```)"), code_span("`[^`]*`");
  static const std::regex reference(R"(^ {0,3}\[[^\]]+\]:\s*<?([^\s>]+))");
  static const std::regex inline_link(R"(\[[^\]]*\]\(\s*<?([^)\s>]*)>?(\s+"[^"]*")?\s*\))");
  std::vector<std::string> targets;
  std::istringstream lines(text);
  std::string line, prose;
  bool in_fence = false;
  while (std::getline(lines, line)) {
    if (std::regex_search(line, fence)) {
      in_fence = !in_fence;
      continue;
    }
    if (in_fence) continue;
    line = std::regex_replace(line, code_span, "``");
    std::smatch m;
    if (std::regex_search(line, m, reference)) targets.push_back(m[1]);
    prose += line + "\n";
  }
  for (std::sregex_iterator it(prose.begin(), prose.end(), inline_link), end; it != end; ++it)
    targets.push_back((*it)[1]);
  return targets;
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
  for (const fs::path& page : markdown_files) {
    std::ifstream in(page, std::ios::binary);
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    const std::string name = fs::weakly_canonical(page).lexically_relative(top).generic_string();
    if (!in) problems.push_back(name + ": cannot be read");
    for (const char* outside : {"../shared", "/work/"})
      if (text.find(outside) != std::string::npos)
        problems.push_back(name + ": names \"" + outside + "\", a path outside the repository");
    for (const std::string& target : link_targets(text)) {
      if (target.empty() || starts_with(target, "#") || starts_with(target, "http://") ||
          starts_with(target, "https://") || starts_with(target, "mailto:"))
        continue;
      const fs::path file = target.substr(0, target.find('#'));
      const std::string where = name + ": link " + target;
      if (file.is_absolute() || file.has_root_name() || file.has_root_directory()) {
        problems.push_back(where + " is an absolute path");
        continue;
      }
      const fs::path resolved = fs::weakly_canonical(page.parent_path() / file);
      if (!inside(resolved, top))
        problems.push_back(where + " leaves the repository");
      else if (!fs::exists(resolved))
        problems.push_back(where + " names no file");
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

TEST(DocsLinks, TheCheckerReportsABrokenLinkAndALinkOutOfTheRepository) {
  const fs::path root =
      fs::temp_directory_path() / ("docs_links_test_" + std::to_string(std::random_device{}()));
  fs::create_directories(root / "docs");
  std::ofstream(root / "README.md") << "# Top\n";
  std::ofstream(root / "docs" / "page.md")
      << "A [broken link](missing.md), a [good one](../README.md#top), an ![image out of the\n"
         "repository](../../outside.png), [the web](https://example.org) and [an anchor](#top).\n"
         "```sh\n[not a link](nowhere.md)\n```\n";
  const std::vector<std::string> problems = link_problems(root, {root / "docs" / "page.md"});
  fs::remove_all(root);
  ASSERT_EQ(problems.size(), 2u) << ::testing::PrintToString(problems);
  EXPECT_NE(problems[0].find("missing.md names no file"), std::string::npos) << problems[0];
  EXPECT_NE(problems[1].find("../../outside.png leaves the repository"), std::string::npos)
      << problems[1];
}
