#pragma once
// The map creator: draws the JSON map format (docs/maps.md) and saves files the json map plugin reads.
// The document is a MapData; every edit replaces it through the undo stack (maps are small, so an
// edit keeps the whole map before and after). Problems (core map_problems) are listed live and the
// shapes they name drawn red; a map with problems is not saved.
#include <QString>
#include <QWidget>
#include <optional>
#include <string>
#include <vector>

#include "salsa/core/model/map_check.hpp"
#include "salsa/core/plugins/plugin_host.hpp"

class QUndoStack;
class QListWidget;
class QLabel;
class QCheckBox;
class QActionGroup;

namespace salsa::gui {

class NumberField;

class MapCanvas;

class MapEditor : public QWidget {
  Q_OBJECT
 public:
  enum class Tool { select, line, polygon, hollow, spawn, bounds };
  /// A selected shape, or the spawn point (Part::spawn).
  struct Selection {
    MapProblem::Part part;
    std::size_t index = 0;
    bool operator==(const Selection&) const = default;
  };

  /// `host` reads and checks saved maps (its json map plugin) and outlives the editor.
  explicit MapEditor(const PluginHost& host, QWidget* parent = nullptr);
  ~MapEditor() override;

  /// Starts an empty map with these bounds (m), the spawn at their centre. Undoable.
  void new_map(Rect bounds);
  /// "" or the CLI's one-line reason (also shown in a dialog); a refused file changes nothing.
  std::string load(const QString& file);
  /// Refused (nothing written) while the map has problems or the core would not read it back.
  std::string save(const QString& file);
  const QString& file() const { return file_; }
  /// Why the map cannot be saved now ("" when it can): Save as refuses it before asking for a name.
  std::string save_problem() const;
  /// Save as: the file dialog, unless save_problem() refuses first. "" or the reason ("cancelled").
  std::string save_as_dialog();

  const MapData& map() const { return map_; }
  const std::vector<MapProblem>& problems() const { return problems_; }
  QUndoStack* undo_stack() const { return undo_; }
  void set_tool(Tool tool);
  Tool tool() const { return tool_; }
  /// Grid step in m for snapping (0: off).
  void set_snap(double metres);
  double snap() const { return snap_; }
  const std::optional<Selection>& selection() const { return selection_; }
  void select(std::optional<Selection> s);
  void delete_selected();
  /// Cancels the shape being drawn (Esc).
  void cancel_draft();
  void fit();

  QWidget* canvas() const;
  QPoint to_px(Vec2 p) const;
  Vec2 to_world(QPointF px) const;
  const QString& last_message() const { return last_message_; }

 Q_SIGNALS:
  void map_saved(const QString& file);
  /// "Use in sandbox": saved to `file`, to be opened there.
  void use_in_sandbox(const QString& file);

 private:
  friend class MapCanvas;
  void edit(const QString& what, MapData after);  ///< one undoable step
  void set_map(const MapData& map);               ///< undo/redo land here
  void refresh();                                  ///< problems, labels, repaint
  void show_message(const QString& text, bool error = true);

  const PluginHost& host_;
  MapData map_;
  std::vector<MapProblem> problems_;
  QString file_;
  Tool tool_ = Tool::select;
  double snap_ = 5;
  std::optional<Selection> selection_;
  QUndoStack* undo_ = nullptr;
  MapCanvas* canvas_ = nullptr;
  QListWidget* problem_list_ = nullptr;
  QLabel* status_ = nullptr;  ///< cursor position, file, counts
  QLabel* hint_ = nullptr;    ///< what the current tool does
  QString hints_[6];
  QCheckBox* snap_on_ = nullptr;
  NumberField* snap_step_ = nullptr;
  QActionGroup* tools_ = nullptr;
  QString last_message_;
};

}  // namespace salsa::gui
