#pragma once
// "Add sweep": the dialog that makes a queue's sweep over the sandbox's test, counting its tests as you type.
#include <QWidget>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/plugins/plugin_host.hpp"

class QComboBox;
class QLabel;
class QLineEdit;
class QListWidget;

namespace salsa::gui {

class NumberField;

/// "Add sweep": behaviors, parameter values, swarm sizes, repeats and the queue seed over the sandbox's
/// test; shows how many tests it makes (or why it is refused) as you type.
class SweepDialog : public QWidget {
  Q_OBJECT
 public:
  SweepDialog(std::shared_ptr<const PluginHost> host, const TestSpec& base, QWidget* parent = nullptr, QueueOptions options = {});
  /// The sweep as a queue file's JSON.
  std::string queue_json(std::string* why) const;
  /// The tests it makes, expanded by the core (load_queue), or nullopt with `why`.
  std::optional<std::vector<TestSpec>> expand(std::string* why) const;
  // For tests and the dialog's owner.
  QListWidget* behaviors() const { return behaviors_; }
  void set_axis(int row, const QString& behavior_param, const QString& values);  ///< "flocking.cohesion_weight", "1, 2"
  QLineEdit* drones() const { return drones_; }
  NumberField* repeats() const { return repeats_; }
  QLineEdit* seed() const { return seed_; }
  QLabel* count_label() const { return count_; }

 Q_SIGNALS:
  void changed();

 private:
  void update_count();
  std::shared_ptr<const PluginHost> host_;
  TestSpec base_;
  QueueOptions options_;
  QListWidget* behaviors_ = nullptr;
  std::vector<std::pair<QComboBox*, QLineEdit*>> axes_;
  QLineEdit* drones_ = nullptr;
  NumberField* repeats_ = nullptr;
  QLineEdit* seed_ = nullptr;
  QLabel* count_ = nullptr;
};

}  // namespace salsa::gui
