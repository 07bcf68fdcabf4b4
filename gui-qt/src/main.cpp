// salsa-gui: the desktop (sandbox, queue mode, map creator, tune mode, replay); `--headless FILE...` runs tests like `salsa run`;
// `--bench-render` measures drawing, `--bench-replay` replay's seeks and playback. Plugins come from the same folders as the CLI's.
#include <unistd.h>

#include <QApplication>
#include <QDir>
#include <QFileInfo>
#include <QScreen>
#include <QTimer>
#include <QWindow>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench_render.hpp"
#include "bench_replay.hpp"
#include "main_window.hpp"
#include "map_editor.hpp"
#include "queue_page.hpp"
#include "replay_page.hpp"
#include "tune_page.hpp"
#include "salsa/core/plugins/plugin_host.hpp"

namespace {

constexpr const char* usage = R"(usage: salsa-gui [TEST.json] [options]
       salsa-gui --headless TEST.json... [salsa run options]   run tests without a window, exactly as `salsa run`
       salsa-gui --bench-render [--frames N] [--drones N] [--physics box2d|light] [--behavior NAME] [--seconds S]
                                                                frame times at 1920x1080, 1,000 drones (default; up to
                                                                100,000), 50,000 trees on 2 km x 2 km (grown past 10,000 drones);
                                                                then FPS and real-time factor flying in real time for S s (default 10)
       salsa-gui --bench-replay FOLDER                          replay of a finished test: seek time and playback FPS at 1920x1080

options:
  --plugin-dir DIR     also search DIR for plugins (repeatable, searched first)
  --start              start running at once
  --view LIST          what the view shows, e.g. heat,camera,-trails (camera, obstacle, detection,
                       targets, trails, heat, obstacles, spawn, links, wind; a leading - hides)
  --select ID          inspect drone ID (with --replay: in the runs replayed)
  --mode MODE          start in sandbox, queue, map (the map creator), tune or replay
  --queue FILE         open a queue file in queue mode (implies --mode queue)
  --run-queue DIR      run the opened queue into DIR at once
  --yes                allow queues of more than 10,000 tests (open, sweep and run them; salsa run gets --yes)
  --edit-map FILE      open a map file in the map creator (implies --mode map)
  --replay FOLDER [FOLDER2]
                       play back a finished test's folder (implies --mode replay); a second folder side by side
  --seek SECONDS       with --replay: put the playhead there
  --run-tune DIR       tune the sandbox's test with tune mode's settings into DIR at once (implies --mode tune)
  --show-plugins       open the Plugins dialog
  --screenshot FILE    save a screenshot of the window (or, under X, of the screen) after --after seconds, then quit
  --after SECONDS      when to take the screenshot (default 3)
  -h, --help           this text
)";

/// The `salsa` program installed (or built) beside this one.
std::string sibling_salsa(const char* argv0) {
  std::error_code ec;
  std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) self = std::filesystem::absolute(argv0);
  return (self.parent_path() / "salsa").string();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && args[0] == "--headless") {
    // One implementation of running tests: hand over to `salsa run` (same options, output and exit codes).
    const std::string salsa = sibling_salsa(argv[0]);
    std::vector<char*> child{const_cast<char*>(salsa.c_str()), const_cast<char*>("run")};
    for (int i = 2; i < argc; ++i) child.push_back(argv[i]);
    child.push_back(nullptr);
    execv(salsa.c_str(), child.data());
    std::cerr << "salsa-gui: --headless needs the salsa program beside salsa-gui: " << salsa << ": " << std::strerror(errno) << "\n";
    return 2;
  }

  std::vector<std::filesystem::path> plugin_dirs;
  std::string test, screenshot, view, mode, queue, run_queue, edit_map, run_tune, bench_replay;
  std::vector<std::string> replay;
  std::optional<double> seek;
  bool show_plugins = false, yes = false;
  std::optional<std::uint32_t> select;
  double after = 3;
  bool start = false, bench = false;
  salsa::gui::BenchRenderOptions bench_options;
  bool bench_only = false;  // an option that only the benchmark takes
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](const char* what) -> std::string {
      if (i + 1 >= args.size()) {
        std::cerr << "salsa-gui: " << a << " needs " << what << "\n";
        std::exit(2);
      }
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      std::cout << usage;
      return 0;
    } else if (a == "--plugin-dir") {
      plugin_dirs.emplace_back(value("a folder"));
    } else if (a == "--start") {
      start = true;
    } else if (a == "--view") {
      view = value("a list such as heat,camera");
    } else if (a == "--select") {
      const std::string v = value("a drone id");
      try {
        select = static_cast<std::uint32_t>(std::stoul(v));
      } catch (const std::exception&) {
        std::cerr << "salsa-gui: --select: '" << v << "' is not a drone id (allowed: whole number ≥ 0)\n";
        return 2;
      }
    } else if (a == "--mode") {
      mode = value("sandbox, queue, map, tune or replay");
      if (mode != "sandbox" && mode != "queue" && mode != "map" && mode != "tune" && mode != "replay") {
        std::cerr << "salsa-gui: --mode: '" << mode << "' is not a mode (allowed: sandbox, queue, map, tune, replay)\n";
        return 2;
      }
    } else if (a == "--queue") {
      queue = value("a queue file");
    } else if (a == "--run-queue") {
      run_queue = value("an output folder");
    } else if (a == "--replay") {
      replay = {value("a finished test's folder")};
      if (i + 1 < args.size() && !args[i + 1].empty() && args[i + 1][0] != '-') replay.push_back(args[++i]);
    } else if (a == "--seek") {
      const std::string v = value("seconds");
      try {
        seek = std::stod(v);
      } catch (const std::exception&) {
        seek = -1;
      }
      if (!(*seek >= 0 && std::isfinite(*seek))) {
        std::cerr << "salsa-gui: --seek: '" << v << "' is out of range (allowed: seconds ≥ 0)\n";
        return 2;
      }
    } else if (a == "--bench-replay") {
      bench_replay = value("a finished test's folder");
    } else if (a == "--run-tune") {
      run_tune = value("an output folder");
    } else if (a == "--edit-map") {
      edit_map = value("a map file");
    } else if (a == "--yes") {
      yes = true;
    } else if (a == "--show-plugins") {
      show_plugins = true;
    } else if (a == "--screenshot") {
      screenshot = value("a file name");
    } else if (a == "--after") {
      const std::string v = value("seconds");
      try {
        after = std::stod(v);
      } catch (const std::exception&) {
        after = -1;
      }
      if (!(after >= 0 && after <= 3600)) {
        std::cerr << "salsa-gui: --after: '" << v << "' is out of range (allowed: [0, 3600] s)\n";
        return 2;
      }
    } else if (a == "--bench-render") {
      bench = true;
    } else if (a == "--frames" || a == "--drones") {
      const std::string v = value("a count");
      const int low = a == "--frames" ? 10 : 1, high = a == "--frames" ? 100000 : salsa::gui::BenchRenderOptions::max_drones;
      int n = 0;
      std::size_t used = 0;
      try {
        n = std::stoi(v, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != v.size() || n < low || n > high) {
        std::cerr << "salsa-gui: " << a << ": '" << v << "' is out of range (allowed: whole number in [" << low << ", " << high << "])\n";
        return 2;
      }
      (a == "--frames" ? bench_options.frames : bench_options.drones) = n;
      bench_only = true;
    } else if (a == "--behavior") {
      bench_options.behavior = value("a behavior's name");
      bench_only = true;
    } else if (a == "--seconds") {
      const std::string v = value("seconds");
      double s = -1;
      std::size_t used = 0;
      try {
        s = std::stod(v, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      using O = salsa::gui::BenchRenderOptions;
      if (used == 0 || used != v.size() || !(s >= O::min_seconds && s <= O::max_seconds)) {
        std::cerr << "salsa-gui: --seconds: '" << v << "' is out of range (allowed: [" << O::min_seconds << ", " << O::max_seconds << "] s)\n";
        return 2;
      }
      bench_options.seconds = s;
      bench_only = true;
    } else if (a == "--physics") {
      bench_options.physics = value("box2d or light");
      if (bench_options.physics != "box2d" && bench_options.physics != "light") {
        std::cerr << "salsa-gui: --physics: '" << bench_options.physics << "' is not a physics (allowed: box2d, light)\n";
        return 2;
      }
      bench_only = true;
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << "salsa-gui: unknown option '" << a << "'\n" << usage;
      return 2;
    } else if (test.empty()) {
      test = a;
    } else {
      std::cerr << "salsa-gui: one test file at a time (got '" << test << "' and '" << a << "'); use --headless to run several\n";
      return 2;
    }
  }

  if (seek && replay.empty()) {
    std::cerr << "salsa-gui: --seek goes with --replay\n";
    return 2;
  }
  if (bench_only && !bench) {
    std::cerr << "salsa-gui: --frames, --drones, --physics, --behavior and --seconds go with --bench-render (a test's own physics is its \"physics\" field)\n";
    return 2;
  }

  QApplication app(argc, argv);
  if (!bench_replay.empty()) return salsa::gui::bench_replay(bench_replay, std::cout);  // no plugin: a recording needs none
  QApplication::setOrganizationName("salsa");
  QApplication::setApplicationName("salsa-gui");
  auto shared_host = std::make_shared<salsa::PluginHost>();
  salsa::PluginHost& host = *shared_host;
  host.load(salsa::PluginHost::default_search_path(plugin_dirs));
  for (const auto& f : host.failures()) std::cerr << "salsa-gui: " << f.file.string() << " skipped: " << f.reason << "\n";
  if (host.behaviors().empty()) {
    std::cerr << "salsa-gui: no behavior plugins found (searched:";
    for (const auto& d : host.searched()) std::cerr << " " << d.path.string();
    std::cerr << ")\n";
    return 1;
  }
  if (bench) {
    try {
      host.behavior(bench_options.behavior);
    } catch (const std::exception& e) {
      std::cerr << "salsa-gui: --behavior: " << e.what() << "\n";
      return 2;
    }
    return salsa::gui::bench_render(host, std::cout, bench_options);
  }

  salsa::gui::MainWindow window(shared_host, plugin_dirs);
  window.queue_page()->set_allow_large(yes);
  // 1600 x 1000, or the screen's free area when smaller (a 1366 x 768 laptop); the offscreen platform
  // (scripted screenshots) keeps the full size.
  QSize size(1600, 1000);
  if (QGuiApplication::platformName() != "offscreen" && window.screen()) size = size.boundedTo(window.screen()->availableGeometry().size());
  window.resize(size);
  window.show();
  if (!test.empty() && !window.sandbox()->open_test(QString::fromStdString(test)).empty()) {
    if (!screenshot.empty()) return 1;  // scripted: the message was shown; nothing to capture
  }
  if (!view.empty()) {
    salsa::gui::ViewOptions o = window.sandbox()->view()->options();
    std::stringstream items(view);
    for (std::string item; std::getline(items, item, ',');) {
      const bool on = item.empty() || item[0] != '-';
      const std::string name = on ? item : item.substr(1);
      bool salsa::gui::ViewOptions::*flag = name == "camera"      ? &salsa::gui::ViewOptions::camera_range
                                           : name == "obstacle"    ? &salsa::gui::ViewOptions::obstacle_range
                                           : name == "detection"   ? &salsa::gui::ViewOptions::detection_range
                                           : name == "targets"     ? &salsa::gui::ViewOptions::targets
                                           : name == "trails"      ? &salsa::gui::ViewOptions::trails
                                           : name == "heat"        ? &salsa::gui::ViewOptions::heat_map
                                           : name == "obstacles"   ? &salsa::gui::ViewOptions::obstacles
                                           : name == "spawn"       ? &salsa::gui::ViewOptions::spawn
                                           : name == "links"       ? &salsa::gui::ViewOptions::links
                                           : name == "wind"        ? &salsa::gui::ViewOptions::wind
                                                                   : nullptr;
      if (!flag) {
        std::cerr << "salsa-gui: --view: unknown item '" << name
                  << "' (allowed: camera, obstacle, detection, targets, trails, heat, obstacles, spawn, links, wind)\n";
        return 2;
      }
      o.*flag = on;
    }
    window.set_view_options(o);
  }
  if (select) window.sandbox()->engine().select(select);
  if (start) window.sandbox()->start();
  using Mode = salsa::gui::MainWindow::Mode;
  if (!queue.empty()) {
    if (!window.queue_page()->open(QString::fromStdString(queue)).empty() && !screenshot.empty()) return 1;
    if (mode.empty()) mode = "queue";
  }
  if (!run_queue.empty() && !window.queue_page()->run(QString::fromStdString(run_queue)).empty() && !screenshot.empty()) return 1;
  if (!edit_map.empty()) {
    if (!window.map_editor()->load(QString::fromStdString(edit_map)).empty() && !screenshot.empty()) return 1;
    if (mode.empty()) mode = "map";
  }
  if (mode == "queue") window.set_mode(Mode::queue);
  if (mode == "map") window.set_mode(Mode::map_creator);
  if (!run_tune.empty() && mode.empty()) mode = "tune";
  if (mode == "tune") window.set_mode(Mode::tune);
  if (!run_tune.empty() && !window.tune_page()->run(QString::fromStdString(run_tune)).empty() && !screenshot.empty()) return 1;
  if (!replay.empty()) {
    for (std::size_t k = 0; k < replay.size(); ++k) {
      salsa::gui::ReplayPage* page = window.replay_page();
      const QString folder = QString::fromStdString(replay[k]);
      if (const std::string why = k == 0 ? page->open(folder) : page->compare(folder); !why.empty()) {
        std::cerr << "salsa-gui: " << why << "\n";  // shown in the window too, which stays up
        if (!screenshot.empty()) return 2;
      }
    }
    if (seek) window.replay_page()->player().seek(*seek);
    if (select) window.replay_page()->select(select);
    if (mode.empty()) mode = "replay";
  }
  if (mode == "replay") window.set_mode(Mode::replay);
  if (show_plugins) window.show_plugins();
  if (!screenshot.empty()) {
    QTimer::singleShot(static_cast<int>(after * 1000), &window, [&] {
      // Under X (xvfb-run) grab the screen as a person sees it; offscreen, the window draws itself.
      QScreen* screen = window.windowHandle() ? window.windowHandle()->screen() : nullptr;
      QPixmap shot = QGuiApplication::platformName() == "xcb" && screen
                         ? screen->grabWindow(0, window.x(), window.y(), window.frameGeometry().width(), window.frameGeometry().height())
                         : window.grab();
      if (!shot.save(QString::fromStdString(screenshot))) {
        std::cerr << "salsa-gui: " << screenshot << ": cannot write the screenshot\n";
        QApplication::exit(1);
        return;
      }
      std::cout << screenshot << "\n";
      QApplication::quit();
    });
  }
  return QApplication::exec();
}
