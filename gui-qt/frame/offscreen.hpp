#pragma once
// Drawing without a display: QtGui needs a QGuiApplication for its fonts, and a program that draws
// frames but shows no window (salsa export --video, the Python package's render) may have none.

namespace salsa::gui {

/// Makes sure this process has a QGuiApplication: when it has no QCoreApplication, makes one on the
/// offscreen platform (whatever QT_QPA_PLATFORM and DISPLAY say) and keeps it for the process's life, so
/// nothing opens a window or needs a display. False when the process already has a QCoreApplication
/// that is not a QGuiApplication (it cannot draw text, and a second one cannot be made).
bool ensure_gui_application();

}  // namespace salsa::gui
