// The table data/bad/expected.tsv through the library: unreadable files throw InputError with the
// expected message; invalid solids are reported by validation; usable ones carry the notice.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "mesh/alpha_wrap.h"
#include "mesh/read_mesh.h"
#include "mesh/validate_mesh.h"
#include "test_scale.h"
#include "util/error.h"

namespace cdbench {
namespace {

struct Row {
  std::string file;
  int code;
  std::string message;
};

std::vector<Row> load_table() {
  std::ifstream in(std::string(CDBENCH_DATA_DIR) + "/bad/expected.tsv");
  std::vector<Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    Row r;
    std::string code;
    std::getline(ls, r.file, '\t');
    std::getline(ls, code, '\t');
    std::getline(ls, r.message);
    r.code = std::stoi(code);
    rows.push_back(r);
  }
  return rows;
}

TEST(BadInputs, TableHasAtLeastFifteenMalformedFiles) {
  const auto rows = load_table();
  EXPECT_GE(std::count_if(rows.begin(), rows.end(), [](const Row& r) { return r.code != 0; }), 15);
}

TEST(BadInputs, EachGivesItsExpectedError) {
  for (const Row& row : load_table()) {
    SCOPED_TRACE(row.file);
    const std::string path = std::string(CDBENCH_DATA_DIR) + "/bad/" + row.file;
    std::string text;
    int code = 0;
    try {
      const ValidatedMesh v = validate_mesh(read_polygon_soup(path));
      for (const auto& e : v.report.errors) text += e.message + "\n";
      for (const auto& n : v.report.notices) text += n + "\n";
      code = v.report.valid() ? 0 : 1;
      if (v.report.valid()) text += "valid closed solid\n";  // the verdict line of 'cdbench check'
    } catch (const InputError& e) {
      text = e.what();
      code = 2;
    }
    EXPECT_EQ(code, row.code) << text;
    EXPECT_NE(text.find(row.message), std::string::npos) << "message: " << text;
  }
}

}  // namespace
}  // namespace cdbench

namespace cdbench {
namespace {

// The motivating real-world case: both problems named, then repaired by alpha wrapping.
TEST(BadInputs, ChineseDragonFromCgalDataAndItsWrap) {
  const std::string path = std::string(CDBENCH_DATA_DIR) + "/cgal/meshes/ChineseDragon-10kv.off";
  if (!std::ifstream(path)) GTEST_SKIP() << "CGAL data not extracted: " << path;
  const PolygonSoup soup = read_polygon_soup(path);
  const ValidatedMesh v = validate_mesh(soup);
  EXPECT_TRUE(v.report.has("boundary"));
  EXPECT_TRUE(v.report.has("self-intersection"));
  for (const auto& e : v.report.errors)
    if (e.kind == "self-intersection") {
      EXPECT_EQ(e.count, 38u);
    }
  // A coarser wrap under the sanitizers: the same CGAL code, a fifth of the faces.
  AlphaWrapOptions wo;
  wo.relative_alpha = test_scale::pick(100.0, 40.0);
  wo.relative_offset = test_scale::pick(3000.0, 1200.0);
  const ValidatedMesh wrapped = validate_mesh(alpha_wrap(soup, wo).mesh);
  EXPECT_TRUE(wrapped.report.valid());
  EXPECT_TRUE(wrapped.report.closed);
}

}  // namespace
}  // namespace cdbench
