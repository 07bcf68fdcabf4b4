#include "offscreen.hpp"

#include <QGuiApplication>

namespace salsa::gui {

bool ensure_gui_application() {
  if (QCoreApplication* app = QCoreApplication::instance()) return qobject_cast<QGuiApplication*>(app) != nullptr;
  // -platform wins over QT_QPA_PLATFORM: a user's xcb or wayland would need the display this avoids.
  static int argc = 3;
  static char name[] = "salsa", option[] = "-platform", platform[] = "offscreen";
  static char* argv[] = {name, option, platform, nullptr};
  // Its start-up notes (no XDG_RUNTIME_DIR, ...) are about a desktop session this process does not have.
  const QtMessageHandler previous = qInstallMessageHandler([](QtMsgType, const QMessageLogContext&, const QString&) {});
  new QGuiApplication(argc, argv);  // never destroyed: it lives as long as the process, as Qt expects
  qInstallMessageHandler(previous);
  return true;
}

}  // namespace salsa::gui
