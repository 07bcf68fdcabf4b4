#include "salsa_process.hpp"

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QLabel>
#include <QMessageBox>
#include <QPlainTextEdit>

namespace salsa::gui {

SalsaProcess::SalsaProcess(QPlainTextEdit* log, QObject* parent)
    : QObject(parent), log_(log), program_(QCoreApplication::applicationDirPath() + "/salsa") {
  connect(&process_, &QProcess::readyReadStandardOutput, this, [this] { read(QProcess::StandardOutput); });
  connect(&process_, &QProcess::readyReadStandardError, this, [this] { read(QProcess::StandardError); });
  connect(&process_, &QProcess::finished, this, [this](int code, QProcess::ExitStatus how) {
    read(QProcess::StandardOutput);
    read(QProcess::StandardError);
    poll_.stop();
    Q_EMIT finished(code, how == QProcess::CrashExit);
  });
  connect(&process_, &QProcess::errorOccurred, this, [this](QProcess::ProcessError e) {
    if (e != QProcess::FailedToStart) return;
    poll_.stop();
    Q_EMIT failed_to_start("cannot start " + program_ + ": " + process_.errorString() + " (salsa is installed beside salsa-gui)");
  });
  poll_.setInterval(500);
  connect(&poll_, &QTimer::timeout, this, &SalsaProcess::poll);
}

SalsaProcess::~SalsaProcess() {
  if (!running()) return;
  process_.blockSignals(true);  // the page it reports to is going away
  process_.terminate();  // salsa stops between tests; --resume picks up the rest
  if (!process_.waitForFinished(5000)) process_.kill();
}

void SalsaProcess::start(const QStringList& args) {
  log_->clear();
  log_->appendPlainText("salsa " + args.join(' '));
  process_.start(program_, args);
  poll_.start();
}

void SalsaProcess::stop() {
  if (running()) process_.terminate();  // salsa stops before the next test; Run into the same folder resumes
}

bool SalsaProcess::wait(int ms) {
  QElapsedTimer t;
  t.start();
  while (running() && t.elapsed() < ms) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
    process_.waitForFinished(50);
  }
  QCoreApplication::processEvents();
  return !running();
}

QString SalsaProcess::last_line() const {
  const QStringList lines = log_->toPlainText().split('\n', Qt::SkipEmptyParts);
  return lines.isEmpty() ? QString() : lines.back();
}

void SalsaProcess::read(QProcess::ProcessChannel channel) {
  process_.setReadChannel(channel);
  bool any = false;
  while (process_.canReadLine()) {
    log_->appendPlainText(QString::fromUtf8(process_.readLine()).trimmed());
    any = true;
  }
  if (any) Q_EMIT printed();
}

void show_state(QLabel* state, QWidget* parent, const QString& text, bool error) {
  state->setText(text);
  state->setStyleSheet(error ? "color: #b00020" : "");
  if (!error) return;
  auto* box = new QMessageBox(QMessageBox::Warning, "salsa", text, QMessageBox::Ok, parent);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
}

}  // namespace salsa::gui
