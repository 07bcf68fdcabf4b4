#pragma once
// A `salsa` command a page runs in the background (queue mode's `salsa run`, tune mode's `salsa tune`):
// the program beside salsa-gui, its output line by line into the page's log, a poll while it runs,
// Stop between tests, and the end told once. The page decides what the end means.
#include <QObject>
#include <QProcess>
#include <QString>
#include <QStringList>
#include <QTimer>

class QLabel;
class QPlainTextEdit;
class QWidget;

namespace salsa::gui {

class SalsaProcess : public QObject {
  Q_OBJECT
 public:
  /// `log` (not owned) receives the command line and every line salsa prints.
  SalsaProcess(QPlainTextEdit* log, QObject* parent);
  /// A run still going is stopped (salsa stops between tests: Run into the same folder resumes it).
  ~SalsaProcess() override;
  /// The `salsa` program (default: the one beside this program).
  void set_program(QString program) { program_ = std::move(program); }
  /// Clears the log, shows the command and starts it; poll() follows every 500 ms while it runs.
  void start(const QStringList& args);
  void stop();
  bool running() const { return process_.state() != QProcess::NotRunning; }
  /// Waits for the run to end, handling events (tests).
  bool wait(int ms);
  /// The last line salsa printed (a refusal is one line on stderr, its last).
  QString last_line() const;

 Q_SIGNALS:
  void printed();                            ///< new lines are in the log
  void poll();                               ///< every 500 ms while it runs
  void finished(int code, bool crashed);     ///< the run ended (all its output is in the log)
  void failed_to_start(const QString& why);  ///< "cannot start PROGRAM: why (salsa is installed beside salsa-gui)"

 private:
  void read(QProcess::ProcessChannel channel);
  QPlainTextEdit* log_;
  QProcess process_;
  QTimer poll_;
  QString program_;
};

/// A page's state line: `text` in `state`, in red for an error, which a dialog over `parent` shows too.
void show_state(QLabel* state, QWidget* parent, const QString& text, bool error);

}  // namespace salsa::gui
