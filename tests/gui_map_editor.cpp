// The map creator as a person uses it: shapes drawn with the mouse (simulated events on the canvas),
// undone and redone, moved and deleted, saved to a file that the core reads and `salsa run` runs on;
// problems (crossing edges, points outside the bounds) are flagged as you draw and block saving.
#include "common.hpp"

#include <QTemporaryDir>
#include <QUndoStack>

#include "map_editor.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa;
using namespace salsa::gui;
using namespace salsa_test;

namespace {

bool same(const Polyline& a, const Polyline& b) { return a == b; }

bool same(const MapData& a, const MapData& b) {
  auto all = [](const std::vector<Polyline>& x, const std::vector<Polyline>& y) {
    return x.size() == y.size() && std::equal(x.begin(), x.end(), y.begin(), [](const Polyline& p, const Polyline& r) { return same(p, r); });
  };
  return a.bounds == b.bounds && a.spawn == b.spawn && all(a.obstacles, b.obstacles) && all(a.hollow, b.hollow) && all(a.lines, b.lines);
}

}  // namespace

class GuiMapEditor : public QObject {
  Q_OBJECT
  std::unique_ptr<PluginHost> host_ = builtin_host();
  QTemporaryDir dir_;

  std::unique_ptr<MapEditor> editor() {
    auto e = std::make_unique<MapEditor>(*host_);
    e->resize(1000, 700);
    e->show();
    if (!QTest::qWaitForWindowExposed(e.get())) return nullptr;
    e->new_map({{0, 0}, {300, 200}});
    e->set_snap(5);
    return e;
  }
  // Mouse gestures at map points (m). `off` px: a hand is never exactly on the grid.
  static void click(MapEditor& e, Vec2 at, QPoint off = {2, -1}) { QTest::mouseClick(e.canvas(), Qt::LeftButton, Qt::NoModifier, e.to_px(at) + off); }
  static void drag(MapEditor& e, Vec2 from, Vec2 to) {
    QTest::mousePress(e.canvas(), Qt::LeftButton, Qt::NoModifier, e.to_px(from) + QPoint(1, 1));
    QTest::mouseMove(e.canvas(), e.to_px((from + to) / 2));
    QTest::mouseMove(e.canvas(), e.to_px(to) + QPoint(-1, 2));
    QTest::mouseRelease(e.canvas(), Qt::LeftButton, Qt::NoModifier, e.to_px(to) + QPoint(-1, 2));
  }
  static void polygon(MapEditor& e, const Polyline& points) {
    for (Vec2 p : points) click(e, p);
    click(e, points.front(), {3, 3});  // close on the first vertex
  }

 private Q_SLOTS:
  // The rules the editor flags by (core map_problems), and every shipped map passes them.
  void map_problems_by_the_rules() {
    MapData m;
    m.bounds = {{0, 0}, {100, 100}};
    m.spawn = {90, 90};
    m.obstacles = {{{10, 10}, {40, 10}, {40, 20}, {20, 20}, {20, 40}, {10, 40}}};  // an L: concave, simple
    QVERIFY(map_problems(m).empty());
    m.obstacles.push_back({{50, 50}, {70, 50}, {60, 50}});  // folds back along itself
    m.hollow = {{{50, 50}, {60, 60}, {60, 50}, {50, 60}}};   // a bow tie
    m.lines = {{{1, 1}}};                                     // one point
    const auto problems = map_problems(m);
    QCOMPARE(problems.size(), std::size_t{3});
    QCOMPARE(problems[0].field, std::string("obstacles[1]"));
    QCOMPARE(problems[1].field, std::string("hollow[0]"));
    QCOMPARE(problems[1].message, std::string("edges 0 and 2 cross (allowed: a simple shape, no edge crossing another)"));
    QCOMPARE(problems[2].message, std::string("line needs at least 2 points, got 1"));
    m.obstacles.pop_back();
    m.hollow.clear();
    m.lines.clear();
    m.spawn = {15, 30};
    QCOMPARE(map_problems(m).at(0).message, std::string("[15, 30] is inside obstacles[0]; drones must start in free space"));
    m.spawn = {100.5, 30};
    QCOMPARE(map_problems(m).at(0).message, std::string("[100.5, 30] is outside the bounds (min [0, 0], max [100, 100])"));
    for (const auto& entry : std::filesystem::directory_iterator(source_dir() / "examples/maps")) {
      const auto found = map_problems(load_map_file(entry.path(), *host_));
      QVERIFY2(found.empty(), (entry.path().string() + ": " + (found.empty() ? "" : found[0].field + ": " + found[0].message)).c_str());
    }
  }

  void draws_undoes_redoes_saves_and_the_core_loads_it() {
    auto e = editor();
    QVERIFY(e);
    const int base = e->undo_stack()->count();

    e->set_tool(MapEditor::Tool::line);
    drag(*e, {20, 20}, {80, 20});
    QCOMPARE(e->map().lines.size(), std::size_t{1});
    QVERIFY(same(e->map().lines[0], Polyline{{20, 20}, {80, 20}}));  // snapped to the 5 m grid

    e->set_tool(MapEditor::Tool::polygon);
    polygon(*e, {{100, 100}, {150, 100}, {150, 150}});
    QCOMPARE(e->map().obstacles.size(), std::size_t{1});
    QVERIFY(same(e->map().obstacles[0], Polyline{{100, 100}, {150, 100}, {150, 150}}));

    e->set_tool(MapEditor::Tool::hollow);
    polygon(*e, {{200, 40}, {260, 40}, {260, 90}, {200, 90}});
    QCOMPARE(e->map().hollow.size(), std::size_t{1});
    QCOMPARE(e->map().hollow[0].size(), std::size_t{4});

    e->set_tool(MapEditor::Tool::spawn);
    click(*e, {40, 150});
    QCOMPARE(e->map().spawn, (Vec2{40, 150}));
    QVERIFY2(e->problems().empty(), e->problems().empty() ? "" : e->problems()[0].message.c_str());
    QCOMPARE(e->undo_stack()->count(), base + 4);

    // Undo and redo, step by step.
    e->undo_stack()->undo();
    QCOMPARE(e->map().spawn, (Vec2{150, 100}));
    e->undo_stack()->undo();
    QVERIFY(e->map().hollow.empty());
    e->undo_stack()->redo();
    e->undo_stack()->redo();
    QCOMPARE(e->map().hollow.size(), std::size_t{1});
    QCOMPARE(e->map().spawn, (Vec2{40, 150}));

    // Move the polygon by dragging it from inside; delete the line with the Delete key.
    e->set_tool(MapEditor::Tool::select);
    drag(*e, {135, 110}, {145, 110});
    QVERIFY(same(e->map().obstacles[0], Polyline{{110, 100}, {160, 100}, {160, 150}}));
    click(*e, {50, 20}, {0, 1});
    QVERIFY(e->selection() && e->selection()->part == MapProblem::Part::line);
    QTest::keyClick(e->canvas(), Qt::Key_Delete);
    QVERIFY(e->map().lines.empty());
    e->undo_stack()->undo();
    QCOMPARE(e->map().lines.size(), std::size_t{1});
    e->undo_stack()->undo();
    QVERIFY(same(e->map().obstacles[0], Polyline{{100, 100}, {150, 100}, {150, 150}}));
    e->undo_stack()->redo();

    // Saved: the core reads back the same map, a fresh editor opens it, salsa run flies in it.
    const QString file = dir_.filePath("drawn.json");
    QCOMPARE(e->save(file), std::string());
    QVERIFY(e->undo_stack()->isClean());
    const MapData back = load_map_file(file.toStdString(), *host_);
    QVERIFY(same(back, e->map()));
    auto other = editor();
    QCOMPARE(other->load(file), std::string());
    QVERIFY(same(other->map(), e->map()));
    QVERIFY(write_file(dir_.filePath("fly.json"), QString(R"({"name": "fly", "behavior": "random_walk", "drones": 5, "targets": {"kind": "tree", "count": 10},
                                                              "map": {"file": "%1"}, "time": 5, "seed": 2})").arg(file).toUtf8()));
    const auto run = run_salsa({"run", dir_.filePath("fly.json"), "--out", dir_.filePath("out"), "--no-plots", "--quiet"});
    QVERIFY2(run.exit_code == 0, describe(run).constData());
    QVERIFY(QFile::exists(dir_.filePath("out/fly/summary.csv")));
  }

  void a_self_intersecting_polygon_is_flagged_and_not_saved() {
    auto e = editor();
    QVERIFY(e);
    const QString file = dir_.filePath("good.json");
    QCOMPARE(e->save(file), std::string());
    const QByteArray good = read_file(file);

    e->set_tool(MapEditor::Tool::polygon);
    polygon(*e, {{50, 50}, {100, 100}, {100, 50}, {50, 100}});  // a bow tie
    QCOMPARE(e->map().obstacles.size(), std::size_t{1});
    QCOMPARE(e->problems().size(), std::size_t{1});
    QCOMPARE(e->problems()[0].field, std::string("obstacles[0]"));
    QVERIFY(QString::fromStdString(e->problems()[0].message).contains("cross"));
    const std::string why = e->save(file);
    QVERIFY(QString::fromStdString(why).contains(file));
    QVERIFY(QString::fromStdString(why).contains("obstacles[0]"));
    QCOMPARE(read_file(file), good);  // the file on disk is untouched
    e->undo_stack()->undo();
    QVERIFY(e->problems().empty());

    // Bounds dragged smaller than a shape: the shape's point outside is named.
    e->set_tool(MapEditor::Tool::line);
    drag(*e, {200, 150}, {280, 150});
    e->set_tool(MapEditor::Tool::bounds);
    drag(*e, {0, 0}, {250, 200});
    QCOMPARE(e->map().bounds, (Rect{{0, 0}, {250, 200}}));
    QVERIFY(!e->problems().empty());
    QCOMPARE(e->problems()[0].field, std::string("lines[0][1]"));
    QVERIFY(QString::fromStdString(e->problems()[0].message).contains("outside"));

    // Esc drops a polygon being drawn.
    e->undo_stack()->undo();
    e->set_tool(MapEditor::Tool::polygon);
    const int edits = e->undo_stack()->count();
    click(*e, {20, 20});
    click(*e, {40, 20});
    QTest::keyClick(e->canvas(), Qt::Key_Escape);
    click(*e, {20, 20});  // not a close: the draft was dropped
    QCOMPARE(e->undo_stack()->count(), edits);
    QCOMPARE(e->map().obstacles.size(), std::size_t{0});
  }

  void a_bad_map_file_keeps_the_drawing() {
    auto e = editor();
    QVERIFY(e);
    e->set_tool(MapEditor::Tool::line);
    drag(*e, {10, 10}, {60, 10});
    const MapData before = e->map();
    const int edits = e->undo_stack()->count();
    const QString bad = dir_.filePath("bad.json");
    QVERIFY(write_file(bad, R"({"bounds": {"min": [0, 0], "max": [5, 5]}, "lines": [[[1, 1], [9, 1]]]})"));
    const std::string why = e->load(bad);
    QCOMPARE(QString::fromStdString(why), bad + ": lines[0][1]: [9, 1] is outside the bounds (min [0, 0], max [5, 5])");
    QVERIFY(same(e->map(), before));
    QCOMPARE(e->undo_stack()->count(), edits);
  }
};

QTEST_MAIN(GuiMapEditor)
#include "gui_map_editor.moc"
