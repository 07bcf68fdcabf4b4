#include "save_checked.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>

#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QLineEdit>
#include <QMessageBox>

namespace fs = std::filesystem;

namespace salsa::gui {

namespace {

/// "" or why nothing can be written into `dir`.
QString folder_problem(const QString& dir) {
  const QFileInfo info(dir);
  if (!info.exists()) return {};  // created by the save (an output folder), checked then
  if (!info.isDir()) return dir + " is not a folder";
  if (!info.isWritable()) return dir + " is read-only: choose another folder";
  return {};
}

class CheckedSaveDialog : public QFileDialog {
 public:
  CheckedSaveDialog(QWidget* parent, const QString& title, const QString& suggested, const QString& filter,
                    std::function<std::string(const QString&)> check, bool folder)
      : QFileDialog(parent, title, suggested, filter), check_(std::move(check)) {
    setAcceptMode(QFileDialog::AcceptSave);
    setOption(QFileDialog::DontUseNativeDialog);  // native dialogs cannot be kept open on a bad name
    if (folder) {
      // A folder, new (typed) or existing (clicked: a stopped run's, to resume it). Directory mode puts a
      // clicked folder's name in the line; accept() takes it instead of opening it.
      setOption(QFileDialog::ShowDirsOnly);
      setFileMode(QFileDialog::Directory);
      setLabelText(QFileDialog::Accept, "Choose");
      folder_ = true;
    }
    connect(this, &QFileDialog::directoryEntered, this, [this](const QString& dir) { show_folder(dir); });
    show_folder(directory().absolutePath());
  }

  void accept() override {
    // A folder path typed with a trailing slash goes there, as in any file dialog; only a name chooses.
    if (auto* line = findChild<QLineEdit*>("fileNameEdit"); folder_ && line && line->text().endsWith('/') && QFileInfo(line->text()).isDir()) {
      setDirectory(line->text());
      line->clear();
      return;
    }
    const QString file = selectedFiles().value(0);
    if (file.isEmpty()) return QFileDialog::accept();
    const QString parent = QFileInfo(file).absolutePath();
    QString why = folder_problem(parent);  // a file, or an output folder to be made: its parent is written
    if (why.isEmpty() && folder_) why = folder_problem(file);  // an existing output folder is written into
    if (why.isEmpty() && check_) why = QString::fromStdString(check_(file));
    if (!why.isEmpty()) {
      QMessageBox::warning(this, windowTitle(), file + ": " + why);  // the dialog stays open, the name as typed
      return;
    }
    if (folder_) return QDialog::accept();  // QFileDialog's would open an existing folder, or refuse a new one
    QFileDialog::accept();
  }

 private:
  void show_folder(const QString& dir) {
    const QString why = folder_problem(dir);
    setLabelText(QFileDialog::LookIn, why.isEmpty() ? "Look in:" : "Read-only!");
    setToolTip(why);
    setLabelText(QFileDialog::FileName, why.isEmpty() ? "File name:" : "Not here (" + QFileInfo(dir).fileName() + " is read-only):");
  }
  std::function<std::string(const QString&)> check_;
  bool folder_ = false;
};

}  // namespace

QString ask_save_file(QWidget* parent, const QString& title, const QString& suggested, const QString& filter,
                      const std::function<std::string(const QString& file)>& check, bool folder) {
  CheckedSaveDialog d(parent, title, suggested, filter, check, folder);
  if (d.exec() != QDialog::Accepted) return {};
  return d.selectedFiles().value(0);
}

std::string save_checked(const fs::path& file, const std::string& text, const std::function<std::string(const fs::path&)>& read_back) {
  std::string name = ".";  // appended, not "." + ...: GCC 12 warns falsely (-Wrestrict) on that
  name.append(file.filename().string()).append(".saving");
  const fs::path aside = file.parent_path() / name;
  std::string why;
  {
    std::ofstream out(aside, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) why = file.string() + ": cannot write (" + std::strerror(errno) + ")";
  }
  if (why.empty()) {
    try {
      why = read_back(aside);
    } catch (const std::exception& e) {
      why = e.what();
    }
    // The reader names the file it read; the user knows it by the name they chose.
    if (auto at = why.find(aside.string()); at != std::string::npos) why.replace(at, aside.string().size(), file.string());
  }
  std::error_code ec;
  if (why.empty()) {
    fs::rename(aside, file, ec);
    if (ec) why = file.string() + ": cannot write (" + ec.message() + ")";
  }
  if (!why.empty()) fs::remove(aside, ec);
  return why;
}

}  // namespace salsa::gui
