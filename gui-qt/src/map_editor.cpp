#include "map_editor.hpp"

#include <QAction>
#include <QActionGroup>
#include <QCheckBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QKeyEvent>
#include <QLabel>
#include <QListWidget>
#include <QMessageBox>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QPushButton>
#include <QToolBar>
#include <QUndoCommand>
#include <QUndoStack>
#include <QVBoxLayout>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <functional>
#include <filesystem>

#include "salsa/core/files/map_file.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "save_checked.hpp"

namespace fs = std::filesystem;

namespace salsa::gui {
namespace {

using Part = MapProblem::Part;
QString q(const std::string& s) { return QString::fromStdString(s); }

std::vector<Polyline>* shapes_of(MapData& m, Part part) {
  switch (part) {
    case Part::obstacle: return &m.obstacles;
    case Part::hollow: return &m.hollow;
    case Part::line: return &m.lines;
    default: return nullptr;
  }
}
const std::vector<Polyline>* shapes_of(const MapData& m, Part part) { return shapes_of(const_cast<MapData&>(m), part); }

double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double len2 = ab.length_squared();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0;
  return distance(p, a + ab * t);
}

// One edit: the whole map before and after it.
class MapEdit final : public QUndoCommand {
 public:
  MapEdit(const QString& text, MapData before, MapData after, std::function<void(const MapData&)> apply)
      : QUndoCommand(text), before_(std::move(before)), after_(std::move(after)), apply_(std::move(apply)) {}
  void undo() override { apply_(before_); }
  void redo() override { apply_(after_); }

 private:
  MapData before_, after_;
  std::function<void(const MapData&)> apply_;
};

}  // namespace

// ---------------------------------------------------------------- the canvas

// Draws the map and turns mouse gestures into edits. Metres to pixels: `scale_` px per m, y up,
// world (0, 0) at `origin_` px.
class MapCanvas final : public QWidget {
 public:
  explicit MapCanvas(MapEditor& editor) : editor_(editor) {
    setMouseTracking(true);  // the shape being drawn follows the cursor
    setFocusPolicy(Qt::StrongFocus);
    setMinimumSize(400, 300);
    setAutoFillBackground(false);
  }

  QPointF to_px(Vec2 p) const { return {origin_.x() + p.x * scale_, origin_.y() - p.y * scale_}; }
  Vec2 to_world(QPointF px) const { return {(px.x() - origin_.x()) / scale_, (origin_.y() - px.y()) / scale_}; }

  void fit() {
    const Rect& b = editor_.map().bounds;
    const double w = std::max(b.width(), 1.0), h = std::max(b.height(), 1.0);
    scale_ = 0.92 * std::min(width() / w, height() / h);
    const Vec2 c = b.centre();
    origin_ = QPointF(width() / 2.0 - c.x * scale_, height() / 2.0 + c.y * scale_);
    fitted_ = true;
    update();
  }
  void cancel() {
    draft_.clear();
    drag_.reset();
    update();
  }
  const std::vector<Vec2>& draft() const { return draft_; }

 protected:
  void resizeEvent(QResizeEvent*) override {
    if (fitted_ || !zoomed_) fit();
  }

  void paintEvent(QPaintEvent*) override {
    QPainter p(this);
    p.setRenderHint(QPainter::Antialiasing);
    p.fillRect(rect(), QColor(200, 200, 205));
    const MapData& m = editor_.map();
    const QRectF bounds(to_px({m.bounds.min.x, m.bounds.max.y}), to_px({m.bounds.max.x, m.bounds.min.y}));
    p.fillRect(bounds, Qt::white);
    draw_grid(p, m.bounds);
    p.setPen(QPen(QColor(60, 60, 60), 2));
    p.setBrush(Qt::NoBrush);
    p.drawRect(bounds);

    auto flagged = [&](Part part, std::size_t i) {
      const auto& ps = editor_.problems();
      return std::any_of(ps.begin(), ps.end(), [&](const MapProblem& x) { return x.part == part && x.index == i; });
    };
    auto selected = [&](Part part, std::size_t i) { return editor_.selection() == MapEditor::Selection{part, i}; };
    auto polygon = [&](const Polyline& pts) {
      QPolygonF poly;
      for (Vec2 v : pts) poly << to_px(v);
      return poly;
    };
    const QColor red(215, 40, 40), blue(30, 110, 230);
    for (std::size_t i = 0; i < m.obstacles.size(); ++i) {
      const bool bad = flagged(Part::obstacle, i);
      p.setPen(QPen(selected(Part::obstacle, i) ? blue : bad ? red : QColor(50, 50, 50), selected(Part::obstacle, i) ? 3 : 1.5));
      p.setBrush(bad ? QColor(240, 120, 120) : QColor(120, 120, 125));
      p.drawPolygon(polygon(m.obstacles[i]));
    }
    p.setBrush(Qt::NoBrush);
    for (std::size_t i = 0; i < m.hollow.size(); ++i) {
      p.setPen(QPen(selected(Part::hollow, i) ? blue : flagged(Part::hollow, i) ? red : QColor(70, 70, 70), 3, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
      p.drawPolygon(polygon(m.hollow[i]));
    }
    for (std::size_t i = 0; i < m.lines.size(); ++i) {
      p.setPen(QPen(selected(Part::line, i) ? blue : flagged(Part::line, i) ? red : QColor(70, 70, 70), 3, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
      p.drawPolyline(polygon(m.lines[i]));
    }
    if (editor_.selection() && editor_.selection()->part != Part::spawn) {  // vertex handles
      p.setPen(QPen(blue, 1.5));
      p.setBrush(Qt::white);
      for (Vec2 v : (*shapes_of(m, editor_.selection()->part))[editor_.selection()->index]) p.drawRect(QRectF(to_px(v) - QPointF(3, 3), QSizeF(6, 6)));
    }
    // Spawn: a green ring with a cross.
    const QPointF s = to_px(m.spawn);
    const bool spawn_bad = flagged(Part::spawn, 0);
    p.setPen(QPen(editor_.selection() == MapEditor::Selection{Part::spawn, 0} ? blue : spawn_bad ? red : QColor(20, 150, 60), 2.5));
    p.setBrush(Qt::NoBrush);
    p.drawEllipse(s, 8, 8);
    p.drawLine(s - QPointF(12, 0), s + QPointF(12, 0));
    p.drawLine(s - QPointF(0, 12), s + QPointF(0, 12));

    draw_draft(p);
    if (hover_) {  // where the cursor is, and where a click would land
      p.setPen(QColor(60, 60, 60));
      p.drawText(rect().adjusted(8, 0, 0, -6), Qt::AlignLeft | Qt::AlignBottom,
                 QString("x %1 m, y %2 m  →  [%3, %4]").arg(hover_->x, 0, 'f', 1).arg(hover_->y, 0, 'f', 1).arg(cursor_.x).arg(cursor_.y));
    }
  }

  void mousePressEvent(QMouseEvent* e) override {
    setFocus();
    if (e->button() == Qt::RightButton || e->button() == Qt::MiddleButton) {
      pan_from_ = e->position();
      return;
    }
    if (e->button() != Qt::LeftButton) return;
    const Vec2 at = editor_.to_world(e->position());
    const Vec2 p = snapped(at);
    switch (editor_.tool()) {
      case MapEditor::Tool::select: {
        const auto hit = hit_test(e->position());
        editor_.select(hit);
        if (hit) drag_ = Drag{p, editor_.map()};
        break;
      }
      case MapEditor::Tool::line:
      case MapEditor::Tool::bounds: drag_ = Drag{p, editor_.map()}; break;
      case MapEditor::Tool::polygon:
      case MapEditor::Tool::hollow: {
        // Close on the first vertex (within 10 px); otherwise a new vertex.
        if (draft_.size() >= 3 && QLineF(e->position(), to_px(draft_.front())).length() <= 10) {
          MapData after = editor_.map();
          const bool solid = editor_.tool() == MapEditor::Tool::polygon;
          (solid ? after.obstacles : after.hollow).push_back(draft_);
          draft_.clear();
          editor_.edit(solid ? "draw polygon" : "draw hollow polygon", std::move(after));
        } else if (draft_.empty() || !(draft_.back() == p)) {
          draft_.push_back(p);
        }
        break;
      }
      case MapEditor::Tool::spawn: {
        MapData after = editor_.map();
        after.spawn = p;
        editor_.edit("set spawn", std::move(after));
        break;
      }
    }
    cursor_ = p;
    update();
  }

  void mouseMoveEvent(QMouseEvent* e) override {
    if (pan_from_) {
      origin_ += e->position() - *pan_from_;
      pan_from_ = e->position();
      zoomed_ = true;
      fitted_ = false;
      update();
      return;
    }
    const Vec2 at = editor_.to_world(e->position());
    cursor_ = snapped(at);
    hover_ = at;
    if (drag_ && editor_.tool() == MapEditor::Tool::select && editor_.selection()) {
      // A live preview of the move; the edit is made on release.
      editor_.map_ = moved(drag_->before, cursor_ - drag_->from);
      editor_.refresh();
    }
    update();
  }

  void mouseReleaseEvent(QMouseEvent* e) override {
    if (e->button() == Qt::RightButton || e->button() == Qt::MiddleButton) {
      pan_from_.reset();
      return;
    }
    if (e->button() != Qt::LeftButton || !drag_) return;
    const Drag d = *drag_;
    drag_.reset();
    const Vec2 to = snapped(editor_.to_world(e->position()));
    switch (editor_.tool()) {
      case MapEditor::Tool::select:
        if (editor_.selection() && !(to == d.from)) {
          editor_.map_ = d.before;  // the preview goes; the edit makes it for good
          editor_.edit(editor_.selection()->part == Part::spawn ? "move spawn" : "move shape", moved(d.before, to - d.from));
        }
        break;
      case MapEditor::Tool::line:
        if (!(to == d.from)) {
          MapData after = editor_.map();
          after.lines.push_back({d.from, to});
          editor_.edit("draw line", std::move(after));
        }
        break;
      case MapEditor::Tool::bounds:
        if (to.x != d.from.x && to.y != d.from.y) {
          MapData after = editor_.map();
          after.bounds = {{std::min(to.x, d.from.x), std::min(to.y, d.from.y)}, {std::max(to.x, d.from.x), std::max(to.y, d.from.y)}};
          editor_.edit("set bounds", std::move(after));
        }
        break;
      default: break;
    }
    update();
  }

  void wheelEvent(QWheelEvent* e) override {
    // Zoom about the cursor: the point under it stays put.
    const Vec2 under = editor_.to_world(e->position());
    scale_ *= std::pow(1.0015, e->angleDelta().y());
    scale_ = std::clamp(scale_, 1e-4, 1e4);
    const QPointF now = to_px(under);
    origin_ += e->position() - now;
    zoomed_ = true;
    fitted_ = false;
    update();
  }

  void keyPressEvent(QKeyEvent* e) override {
    if (e->key() == Qt::Key_Escape) cancel();
    else if (e->key() == Qt::Key_Delete || e->key() == Qt::Key_Backspace) editor_.delete_selected();
    else QWidget::keyPressEvent(e);
  }

 private:
  struct Drag {
    Vec2 from;
    MapData before;
  };

  Vec2 snapped(Vec2 p) const {
    const double g = editor_.snap();
    return g > 0 ? Vec2{std::round(p.x / g) * g, std::round(p.y / g) * g} : p;
  }

  MapData moved(MapData m, Vec2 by) const {
    const auto& sel = editor_.selection();
    if (!sel) return m;
    if (sel->part == Part::spawn) {
      m.spawn += by;
    } else if (auto* list = shapes_of(m, sel->part); list && sel->index < list->size()) {
      for (Vec2& v : (*list)[sel->index]) v += by;
    }
    return m;
  }

  // The spawn point, then the topmost shape under `px`: an edge within 6 px, or inside a polygon.
  std::optional<MapEditor::Selection> hit_test(QPointF px) const {
    const MapData& m = editor_.map();
    if (QLineF(px, to_px(m.spawn)).length() <= 10) return MapEditor::Selection{Part::spawn, 0};
    const Vec2 w = editor_.to_world(px);
    const double tolerance = 6 / scale_;
    auto near = [&](const Polyline& pts, bool closed) {
      for (std::size_t i = 0; i + 1 < pts.size() + (closed ? 1 : 0); ++i)
        if (distance_to_segment(w, pts[i], pts[(i + 1) % pts.size()]) <= tolerance) return true;
      return pts.size() == 1 && distance(w, pts[0]) <= tolerance;
    };
    for (std::size_t i = m.lines.size(); i-- > 0;)
      if (near(m.lines[i], false)) return MapEditor::Selection{Part::line, i};
    for (std::size_t i = m.hollow.size(); i-- > 0;)
      if (near(m.hollow[i], true)) return MapEditor::Selection{Part::hollow, i};
    for (std::size_t i = m.obstacles.size(); i-- > 0;)
      if (near(m.obstacles[i], true) || (m.obstacles[i].size() >= 3 && inside_polygon(w, m.obstacles[i])))
        return MapEditor::Selection{Part::obstacle, i};
    return std::nullopt;
  }

  void draw_grid(QPainter& p, const Rect& b) const {
    double step = editor_.snap() > 0 ? editor_.snap() : 10;
    while (step * scale_ < 8) step *= 5;  // never denser than 8 px
    p.setPen(QPen(QColor(232, 232, 238), 1));
    for (double x = std::ceil(b.min.x / step) * step; x <= b.max.x; x += step) p.drawLine(to_px({x, b.min.y}), to_px({x, b.max.y}));
    for (double y = std::ceil(b.min.y / step) * step; y <= b.max.y; y += step) p.drawLine(to_px({b.min.x, y}), to_px({b.max.x, y}));
  }

  void draw_draft(QPainter& p) const {
    const QColor ink(30, 110, 230), red(215, 40, 40);
    p.setBrush(Qt::NoBrush);
    if (drag_ && editor_.tool() == MapEditor::Tool::line) {
      p.setPen(QPen(ink, 3, Qt::DashLine));
      p.drawLine(to_px(drag_->from), to_px(cursor_));
    }
    if (drag_ && editor_.tool() == MapEditor::Tool::bounds) {
      p.setPen(QPen(ink, 2, Qt::DashLine));
      p.drawRect(QRectF(to_px(drag_->from), to_px(cursor_)).normalized());
    }
    if (draft_.empty()) return;
    // Flagged as it is drawn: red once the polygon it would close to crosses itself.
    Polyline closing = draft_;
    closing.push_back(cursor_);
    const auto [e1, e2] = crossing_edges(closing);
    const bool bad = e1 != e2;
    QPolygonF line;
    for (Vec2 v : draft_) line << to_px(v);
    p.setPen(QPen(bad ? red : ink, 2.5));
    p.drawPolyline(line);
    p.setPen(QPen(bad ? red : ink, 1.5, Qt::DashLine));
    p.drawLine(line.back(), to_px(cursor_));
    p.setPen(QPen(ink, 1.5));
    p.setBrush(Qt::white);
    for (const QPointF& v : line) p.drawEllipse(v, 3, 3);
    p.setBrush(ink);
    p.drawEllipse(line.front(), 6, 6);  // click here to close
  }

  MapEditor& editor_;
  double scale_ = 1;
  QPointF origin_;
  bool fitted_ = false, zoomed_ = false;
  std::vector<Vec2> draft_;  ///< the polygon being clicked in
  std::optional<Drag> drag_;
  std::optional<QPointF> pan_from_;
  Vec2 cursor_;                ///< the snapped point under the mouse (m)
  std::optional<Vec2> hover_;  ///< the point under the mouse, not snapped (m)
};

// ---------------------------------------------------------------- the editor

MapEditor::MapEditor(const PluginHost& host, QWidget* parent) : QWidget(parent), host_(host) {
  undo_ = new QUndoStack(this);
  canvas_ = new MapCanvas(*this);

  auto* bar = new QToolBar;
  bar->setToolButtonStyle(Qt::ToolButtonTextOnly);
  tools_ = new QActionGroup(this);
  const std::tuple<const char*, Tool, const char*, const char*> tools[] = {
      {"Select", Tool::select, "V", "select, drag to move, Delete to remove"},
      {"Line", Tool::line, "L", "drag from one end to the other: an open wall"},
      {"Polygon", Tool::polygon, "P", "click the vertices, click the first again to close: a solid obstacle (Esc cancels)"},
      {"Hollow", Tool::hollow, "O", "click the vertices, click the first again to close: an outline whose inside is free"},
      {"Spawn", Tool::spawn, "S", "click where the drones start"},
      {"Bounds", Tool::bounds, "B", "drag the rectangle the drones fly in"},
  };
  for (const auto& [text, tool, key, tip] : tools) {
    QAction* a = bar->addAction(text);
    a->setCheckable(true);
    a->setShortcut(QKeySequence(key));
    a->setShortcutContext(Qt::WidgetWithChildrenShortcut);
    a->setToolTip(QString("%1 (%2): %3").arg(text, key, tip));
    a->setData(static_cast<int>(tool));
    tools_->addAction(a);
    addAction(a);
    connect(a, &QAction::triggered, this, [this, tool = tool] { set_tool(tool); });
    hints_[static_cast<int>(tool)] = QString("<b>%1</b>: %2").arg(text, tip);
  }
  tools_->actions().front()->setChecked(true);
  bar->addSeparator();
  QAction* undo = undo_->createUndoAction(this, "Undo");
  undo->setShortcut(QKeySequence::Undo);
  QAction* redo = undo_->createRedoAction(this, "Redo");
  redo->setShortcut(QKeySequence::Redo);
  for (QAction* a : {undo, redo}) {
    a->setShortcutContext(Qt::WidgetWithChildrenShortcut);
    bar->addAction(a);
    addAction(a);
  }
  bar->addAction("Delete", this, &MapEditor::delete_selected);
  bar->addAction("Fit", this, &MapEditor::fit);

  // The side panel: file, grid, problems.
  auto* side = new QWidget;
  side->setFixedWidth(340);
  auto* column = new QVBoxLayout(side);
  auto* files = new QHBoxLayout;
  auto* new_button = new QPushButton("New");
  auto* open_button = new QPushButton("Open…");
  auto* save_button = new QPushButton("Save");
  auto* save_as_button = new QPushButton("Save as…");
  for (auto* b : {new_button, open_button, save_button, save_as_button}) files->addWidget(b);
  column->addLayout(files);
  auto* use = new QPushButton("Save and use in sandbox");
  use->setToolTip("saves the map and opens it in the sandbox");
  column->addWidget(use);
  auto* size_row = new QHBoxLayout;
  auto* width = new QDoubleSpinBox;
  auto* height = new QDoubleSpinBox;
  size_row->addWidget(new QLabel("New map"));
  for (auto* box : {width, height}) {
    box->setRange(10, 100000);
    box->setValue(300);
    box->setDecimals(0);
    box->setSuffix(" m");
    size_row->addWidget(box);
  }
  column->addLayout(size_row);
  snap_on_ = new QCheckBox("Snap to grid");
  snap_on_->setChecked(true);
  snap_step_ = new QDoubleSpinBox;
  snap_step_->setRange(0.1, 1000);
  snap_step_->setValue(snap_);
  snap_step_->setSuffix(" m");
  auto* snap_row = new QHBoxLayout;
  snap_row->addWidget(snap_on_);
  snap_row->addWidget(snap_step_);
  column->addLayout(snap_row);
  auto* problems_title = new QLabel("<b>Problems</b> (drawn red; a map with problems is not saved)");
  problems_title->setWordWrap(true);
  column->addWidget(problems_title);
  problem_list_ = new QListWidget;
  problem_list_->setWordWrap(true);
  problem_list_->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  column->addWidget(problem_list_, 1);
  hint_ = new QLabel;
  hint_->setWordWrap(true);
  column->addWidget(hint_);
  status_ = new QLabel;
  status_->setWordWrap(true);
  column->addWidget(status_);

  auto* body = new QHBoxLayout;
  body->setContentsMargins(0, 0, 0, 0);
  body->addWidget(canvas_, 1);
  body->addWidget(side);
  auto* outer = new QVBoxLayout(this);
  outer->setContentsMargins(0, 0, 0, 0);
  outer->addWidget(bar);
  outer->addLayout(body, 1);

  connect(new_button, &QPushButton::clicked, this, [this, width, height] { new_map({{0, 0}, {width->value(), height->value()}}); });
  connect(open_button, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, "Open map", file_.isEmpty() ? QDir::currentPath() : QFileInfo(file_).path(), "Map files (*.json)");
    if (!f.isEmpty()) load(f);
  });
  connect(save_button, &QPushButton::clicked, this, [this] { file_.isEmpty() ? (void)save_as_dialog() : (void)save(file_); });
  connect(save_as_button, &QPushButton::clicked, this, [this] { save_as_dialog(); });
  connect(use, &QPushButton::clicked, this, [this] {
    if ((file_.isEmpty() ? save_as_dialog() : save(file_)).empty() && !file_.isEmpty()) emit use_in_sandbox(file_);
  });
  auto snap_changed = [this] { snap_ = snap_on_->isChecked() ? snap_step_->value() : 0; canvas_->update(); };
  connect(snap_on_, &QCheckBox::toggled, this, snap_changed);
  connect(snap_step_, &QDoubleSpinBox::valueChanged, this, snap_changed);
  connect(problem_list_, &QListWidget::currentRowChanged, this, [this](int row) {
    if (row < 0 || row >= static_cast<int>(problems_.size())) return;
    const MapProblem& p = problems_[static_cast<std::size_t>(row)];
    if (p.part != Part::bounds) select(Selection{p.part, p.index});
  });
  connect(undo_, &QUndoStack::cleanChanged, this, [this] { refresh(); });

  map_.bounds = {{0, 0}, {300, 300}};
  map_.spawn = map_.bounds.centre();
  set_tool(Tool::select);
  refresh();
}

MapEditor::~MapEditor() { undo_->disconnect(this); }  // a dying stack says it is clean: nothing left to refresh

QWidget* MapEditor::canvas() const { return canvas_; }
QPoint MapEditor::to_px(Vec2 p) const { return canvas_->to_px(p).toPoint(); }
Vec2 MapEditor::to_world(QPointF px) const { return canvas_->to_world(px); }
void MapEditor::fit() { canvas_->fit(); }

void MapEditor::set_tool(Tool tool) {
  canvas_->cancel();
  tool_ = tool;
  for (QAction* a : tools_->actions())
    if (a->data().toInt() == static_cast<int>(tool)) a->setChecked(true);
  if (tool != Tool::select) select(std::nullopt);
  hint_->setText(hints_[static_cast<int>(tool)]);
}

void MapEditor::set_snap(double metres) {
  snap_on_->setChecked(metres > 0);
  if (metres > 0) snap_step_->setValue(metres);
  snap_ = metres > 0 ? metres : 0;
}

void MapEditor::select(std::optional<Selection> s) {
  selection_ = s;
  canvas_->update();
}

void MapEditor::cancel_draft() { canvas_->cancel(); }

void MapEditor::delete_selected() {
  if (!selection_ || selection_->part == Part::spawn) return;  // a map always has a spawn point
  MapData after = map_;
  auto* list = shapes_of(after, selection_->part);
  if (!list || selection_->index >= list->size()) return;
  list->erase(list->begin() + static_cast<std::ptrdiff_t>(selection_->index));
  selection_.reset();
  edit("delete shape", std::move(after));
}

void MapEditor::new_map(Rect bounds) {
  MapData fresh;
  fresh.bounds = bounds;
  fresh.spawn = bounds.centre();
  file_.clear();
  edit("new map", std::move(fresh));
  canvas_->fit();
}

void MapEditor::edit(const QString& what, MapData after) {
  undo_->push(new MapEdit(what, map_, std::move(after), [this](const MapData& m) { set_map(m); }));
}

void MapEditor::set_map(const MapData& map) {
  map_ = map;
  if (selection_ && selection_->part != Part::spawn) {  // the selected shape may be gone
    const auto* list = shapes_of(map_, selection_->part);
    if (!list || selection_->index >= list->size()) selection_.reset();
  }
  refresh();
}

void MapEditor::refresh() {
  problems_ = map_problems(map_);
  const QSignalBlocker quiet(problem_list_);
  problem_list_->clear();
  for (const MapProblem& p : problems_) problem_list_->addItem(q(p.field + ": " + p.message));
  const QString name = file_.isEmpty() ? "untitled" : QFileInfo(file_).fileName();
  setWindowTitle(name + (undo_->isClean() ? "" : " *"));
  status_->setText(QString("%1%2 — %3 obstacles, %4 hollow, %5 lines")
                       .arg(name, undo_->isClean() ? "" : " (unsaved)")
                       .arg(map_.obstacles.size())
                       .arg(map_.hollow.size())
                       .arg(map_.lines.size()));
  canvas_->update();
}

void MapEditor::show_message(const QString& text, bool error) {
  last_message_ = text;
  if (!error) return;
  auto* box = new QMessageBox(QMessageBox::Warning, "salsa", text, QMessageBox::Ok, this);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
}

std::string MapEditor::load(const QString& file) {
  MapData loaded;
  try {
    loaded = load_map_file(file.toStdString(), host_);  // the CLI's reader and checks
  } catch (const std::exception& e) {
    show_message(q(e.what()));
    return e.what();
  }
  map_ = loaded;
  selection_.reset();
  canvas_->cancel();
  undo_->clear();
  file_ = QFileInfo(file).absoluteFilePath();
  refresh();
  canvas_->fit();
  show_message("opened " + file_, false);
  return {};
}

std::string MapEditor::save(const QString& file) {
  const std::string path = file.toStdString();
  if (const std::string problem = save_problem(); !problem.empty()) {
    const std::string why = path + ": " + problem;
    show_message(q(why));
    return why;
  }
  // Read back by the core, as `salsa run` reads it.
  if (const std::string why = save_checked(path, map_json(map_, map_.spawn), [this](const fs::path& aside) {
        (void)load_map_file(aside, host_);
        return std::string();
      });
      !why.empty()) {
    show_message(q(why));
    return why;
  }
  file_ = QFileInfo(file).absoluteFilePath();
  undo_->setClean();
  refresh();
  show_message("saved " + file_, false);
  emit map_saved(file_);
  return {};
}

std::string MapEditor::save_problem() const {
  if (problems_.empty()) return {};
  return "not saved: " + problems_.front().field + ": " + problems_.front().message +
         (problems_.size() > 1 ? " (and " + std::to_string(problems_.size() - 1) + " more problems)" : "");
}

std::string MapEditor::save_as_dialog() {
  // A map with problems is refused before a file name is asked for, not after.
  if (const std::string why = save_problem(); !why.empty()) return show_message(q(why)), why;
  const QString f = ask_save_file(this, "Save map", file_.isEmpty() ? QDir::currentPath() + "/map.json" : file_, "Map files (*.json)");
  return f.isEmpty() ? std::string("cancelled") : save(f);
}

}  // namespace salsa::gui
