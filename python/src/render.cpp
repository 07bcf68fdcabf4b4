// Session.render: the simulation drawn as the desktop draws it (salsa_frame, gui-qt/frame/), into a numpy
// RGB array. QtGui needs a QGuiApplication for its fonts: without one in the process, one on the
// offscreen platform is made and kept, so nothing opens a window or needs a display.
#include <pybind11/numpy.h>

#include <QGuiApplication>
#include <QImage>
#include <cstring>

#include "bindings.hpp"
#include "frame_renderer.hpp"

namespace salsa::python {

namespace {

void ensure_gui_application() {
  if (QCoreApplication* app = QCoreApplication::instance()) {
    if (!qobject_cast<QGuiApplication*>(app))
      throw py::value_error("render: this process has a QCoreApplication without a GUI, which cannot draw text (allowed: "
                            "none, or a QGuiApplication or QApplication)");
    return;
  }
  static int argc = 3;
  static char name[] = "salsa", option[] = "-platform", platform[] = "offscreen";
  static char* argv[] = {name, option, platform, nullptr};
  // Its start-up notes (no XDG_RUNTIME_DIR, ...) are about a desktop session this process does not have.
  const QtMessageHandler previous = qInstallMessageHandler([](QtMsgType, const QMessageLogContext&, const QString&) {});
  new QGuiApplication(argc, argv);  // never destroyed: it lives as long as the process, as Qt expects
  qInstallMessageHandler(previous);
}

}  // namespace

py::array render_session(const Session& session, int width, int height) {
  constexpr int most = 16384;
  for (auto [name, v] : {std::pair{"width", width}, std::pair{"height", height}})
    if (v < 1 || v > most)
      throw py::value_error(std::string(name) + ": " + std::to_string(v) + " is out of range (allowed: whole number of pixels in [1, " +
                            std::to_string(most) + "])");
  ensure_gui_application();
  const Simulation& sim = session.simulation();
  gui::Snapshot snap;
  snap.scene = gui::scene_of(sim);
  gui::fill_snapshot(snap, sim, session.current().has_wind());
  snap.found = gui::found_flags(sim);
  snap.targets_found = sim.targets_found();
  snap.test_name = session.test().name;
  const QImage frame = gui::render_frame(snap, gui::ViewOptions{}, QSize(width, height)).convertToFormat(QImage::Format_RGB888);
  py::array_t<std::uint8_t> out({py::ssize_t{height}, py::ssize_t{width}, py::ssize_t{3}});
  auto* to = out.mutable_data();
  const auto row = static_cast<std::size_t>(width) * 3;
  for (int y = 0; y < height; ++y) std::memcpy(to + static_cast<std::size_t>(y) * row, frame.constScanLine(y), row);
  return out;
}

}  // namespace salsa::python
