// The map creator: its tools, undo stack, problem list and files (the canvas it draws on: map_canvas.cpp).
#include "map_editor.hpp"

#include <QAction>
#include <QActionGroup>
#include <QCheckBox>
#include <QDir>
#include "number_field.hpp"
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QMessageBox>
#include <QPushButton>
#include <QToolBar>
#include <QUndoCommand>
#include <QUndoStack>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <functional>
#include <filesystem>

#include "map_canvas.hpp"
#include "salsa/core/files/map_file.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "save_checked.hpp"

namespace fs = std::filesystem;

namespace salsa::gui {
namespace {

using Part = MapProblem::Part;
QString q(const std::string& s) { return QString::fromStdString(s); }

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
  auto* width = new NumberField({"width", 300, 10, 100000, "m", "", 1});
  auto* height = new NumberField({"height", 300, 10, 100000, "m", "", 1});
  size_row->addWidget(new QLabel("New map"));
  for (auto* box : {width, height}) {
    box->setValue(300);
    size_row->addWidget(box);
  }
  column->addLayout(size_row);
  snap_on_ = new QCheckBox("Snap to grid");
  snap_on_->setChecked(true);
  snap_step_ = new NumberField({"snap", 1, 0.1, 1000, "m", "", 0.1});
  snap_step_->setValue(snap_);
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
  connect(snap_step_, &NumberField::valueChanged, this, snap_changed);
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
