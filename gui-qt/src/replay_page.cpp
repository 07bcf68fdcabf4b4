#include "replay_page.hpp"

#include <QApplication>
#include <QComboBox>
#include <QDateTime>
#include <QFileDialog>
#include <QHBoxLayout>
#include <QLabel>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QShortcut>
#include <QSignalBlocker>
#include <QSlider>
#include <QSplitter>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "inspector_text.hpp"
#include "live_charts.hpp"
#include "recorded_frame.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/files/input_error.hpp"
#include "view.hpp"

namespace salsa::gui {
namespace {
constexpr double trail_seconds = 30;   // each drone's last half minute, whatever the log interval
constexpr std::size_t trail_points = 60000;  // at most, over all drones
constexpr int timeline_ticks = 1000;   // per second: the slider moves in ms
constexpr double speeds[] = {0.25, 0.5, 1, 2, 4, 8, 16, 32, 64};
constexpr int charts_every_ms = 250;   // playing, the plots redraw this often (a seek redraws them at once)
}  // namespace

std::vector<StatsRow> recorded_stats(const Recording& r) {
  constexpr double none = std::numeric_limits<double>::quiet_NaN();
  std::vector<StatsRow> rows;
  std::error_code ec;
  if (const auto file = r.folder / "summary.csv"; std::filesystem::is_regular_file(file, ec)) {
    try {
      CsvReader in(file);
      const std::size_t time = in.column("time");
      const auto found = in.find("fraction_found"), speed = in.find("mean_speed"), nn = in.find("mean_nn_distance"),
                 coverage = in.find("coverage");
      auto value = [&](std::optional<std::size_t> c, double factor) {
        const auto v = c ? in.optional_number(*c) : std::nullopt;
        return v ? *v * factor : none;
      };
      while (in.next())
        rows.push_back({in.number(time), value(found, 100), value(coverage, 100), value(speed, 1), value(nn, 1)});
      return rows;
    } catch (const InputError&) {  // a summary cut short or edited: the recording's own figures instead
      rows.clear();
    }
  }
  const RecordedColumn* velocity = r.column("velocity");
  for (std::size_t f = 0; f < r.frames(); ++f) {
    StatsRow row{r.times[f], r.targets.empty() ? 0.0 : 100.0 * static_cast<double>(r.found_by_time(r.times[f])) / static_cast<double>(r.targets.size()),
                 none, none, none};
    double sum = 0;
    std::size_t flying = 0;
    for (std::size_t id = 0; velocity && id < r.drones; ++id)
      if (r.status(f, id) == 0) sum += Vec2{r.at(*velocity, f, id, 0), r.at(*velocity, f, id, 1)}.length(), ++flying;
    if (velocity) row.mean_speed = flying ? sum / static_cast<double>(flying) : 0;
    rows.push_back(row);
  }
  return rows;
}

std::size_t trail_frames(const Recording& r) {
  const std::size_t frames = r.log_interval > 0 ? static_cast<std::size_t>(std::lround(trail_seconds / r.log_interval)) + 1 : 31;
  // Each new frame redraws every trail (the samples all move on): past trail_points, fewer frames each,
  // so that a big swarm still plays at 60 FPS (docs/replay.md).
  return std::clamp<std::size_t>(std::min(frames, trail_points / std::max<std::size_t>(1, r.drones)), 2, 300);
}

struct ReplayPage::Run {
  std::shared_ptr<const Recording> recording;
  std::shared_ptr<const Scene> scene;
  std::vector<StatsRow> stats;
  std::size_t trail = 0;  ///< frames
  QWidget* pane = nullptr;
  QLabel* title = nullptr;
  SwarmView* view = nullptr;
  std::size_t frame = std::numeric_limits<std::size_t>::max();  ///< the frame shown
  std::shared_ptr<const Snapshot> shown;
  std::shared_ptr<const std::vector<StatsRow>> plotted;  ///< the rows up to the playhead
};

ReplayPage::ReplayPage(QWidget* parent) : QWidget(parent) {
  auto* open = new QPushButton("Open results…");
  connect(open, &QPushButton::clicked, this, &ReplayPage::ask_open);
  compare_ = new QPushButton("Compare with…");
  compare_->setToolTip("Open a second finished test beside this one, in step (the same world with another behavior, or with a condition)");
  connect(compare_, &QPushButton::clicked, this, &ReplayPage::ask_compare);
  auto* back = new QPushButton("◀|");
  back->setToolTip("Previous frame (Left)");
  connect(back, &QPushButton::clicked, this, [this] { player_.step(-1); });
  play_ = new QPushButton("Play");
  play_->setToolTip("Play / pause (Space)");
  connect(play_, &QPushButton::clicked, &player_, &Player::toggle);
  auto* forward = new QPushButton("|▶");
  forward->setToolTip("Next frame (Right)");
  connect(forward, &QPushButton::clicked, this, [this] { player_.step(1); });
  speed_ = new QComboBox;
  speed_->setToolTip("Recorded seconds per second");
  for (double s : speeds) speed_->addItem(QString("%1×").arg(s), s);
  speed_->setCurrentIndex(2);
  connect(speed_, &QComboBox::currentIndexChanged, this, [this](int i) { player_.set_speed(speed_->itemData(i).toDouble()); });
  timeline_ = new QSlider(Qt::Horizontal);
  timeline_->setObjectName("replay_timeline");
  timeline_->setRange(0, 0);
  // Dragging seeks as it goes: a seek draws one frame per run (docs/replay.md gives its cost).
  connect(timeline_, &QSlider::valueChanged, this, [this](int v) { player_.seek(static_cast<double>(v) / timeline_ticks); });
  clock_ = new QLabel;
  clock_->setMinimumWidth(170);

  auto* bar = new QHBoxLayout;
  for (QWidget* w : std::initializer_list<QWidget*>{open, compare_, back, play_, forward, speed_}) bar->addWidget(w);
  bar->addWidget(timeline_, 1);
  bar->addWidget(clock_);

  views_ = new QSplitter(Qt::Horizontal);
  empty_ = new QLabel("File > Open results… (or the button above) opens a finished test's folder and plays it back.");
  empty_->setAlignment(Qt::AlignCenter);
  views_->addWidget(empty_);
  charts_ = new LiveCharts;
  inspector_ = new QPlainTextEdit;
  inspector_->setReadOnly(true);
  inspector_->setPlaceholderText("Click a drone to see its recorded state.");
  auto* side = new QSplitter(Qt::Vertical);
  side->addWidget(charts_);
  side->addWidget(inspector_);
  side->setMinimumWidth(320);  // as the sandbox's plots dock: tick labels readable
  side->setStretchFactor(0, 3);
  side->setStretchFactor(1, 2);
  auto* body = new QSplitter(Qt::Horizontal);
  body->addWidget(views_);
  body->addWidget(side);
  body->setStretchFactor(0, 4);
  body->setStretchFactor(1, 1);
  note_ = new QLabel;
  note_->setObjectName("replay_note");
  note_->setStyleSheet("color: #a00;");
  note_->setWordWrap(true);
  note_->hide();

  auto* layout = new QVBoxLayout(this);
  layout->addLayout(bar);
  layout->addWidget(note_);
  layout->addWidget(body, 1);

  auto key = [this](QKeySequence k, auto fn) {
    auto* s = new QShortcut(k, this, fn);
    s->setContext(Qt::WidgetWithChildrenShortcut);
  };
  key(QKeySequence(Qt::Key_Space), [this] { player_.toggle(); });
  key(QKeySequence(Qt::Key_Left), [this] { player_.step(-1); });
  key(QKeySequence(Qt::Key_Right), [this] { player_.step(1); });

  connect(&player_, &Player::moved, this, [this](double t) { show_time(t); });
  connect(&player_, &Player::playing_changed, this, [this](bool on) {
    play_->setText(on ? "Pause" : "Play");
    if (!on) refresh_side_panels();  // paused: the plots up to the playhead exactly
  });
  runs_changed();
}

ReplayPage::~ReplayPage() = default;

SwarmView* ReplayPage::view(std::size_t run) const { return runs_.at(run)->view; }
const Recording& ReplayPage::recording(std::size_t run) const { return *runs_.at(run)->recording; }
std::shared_ptr<const Snapshot> ReplayPage::shown(std::size_t run) const { return runs_.at(run)->shown; }
QString ReplayPage::title(std::size_t run) const { return runs_.at(run)->title->text(); }

std::string ReplayPage::open(const QString& folder) { return load(folder, 0); }

std::string ReplayPage::compare(const QString& folder) { return load(folder, runs_.empty() ? 0 : 1); }

void ReplayPage::ask_open() {
  const QString f = QFileDialog::getExistingDirectory(this, "Open results: a finished test's folder");
  if (!f.isEmpty()) open(f);
}

void ReplayPage::ask_compare() {
  const QString f = QFileDialog::getExistingDirectory(this, "Compare with: another finished test's folder");
  if (!f.isEmpty()) compare(f);
}

std::string ReplayPage::load(const QString& folder, std::size_t run) {
  auto r = std::make_unique<Run>();
  try {
    QApplication::setOverrideCursor(Qt::WaitCursor);
    r->recording = std::make_shared<const Recording>(load_recording(folder.toStdString()));
    QApplication::restoreOverrideCursor();
  } catch (const std::exception& e) {  // InputError: one line naming the file; anything else is said as it is
    QApplication::restoreOverrideCursor();
    const std::string why = e.what();
    note_->setText(QString::fromStdString(why));
    note_->show();
    Q_EMIT message(QString::fromStdString(why), true);
    return why;
  }
  note_->hide();
  const Recording& rec = *r->recording;
  r->scene = scene_of(rec);
  r->stats = recorded_stats(rec);
  r->trail = trail_frames(rec);
  r->pane = new QWidget;
  r->title = new QLabel;
  r->title->setObjectName("replay_title");
  r->title->setText(QString("<b>%1</b> — %2 drones, %3 s, logged every %4 s")
                        .arg(QString::fromStdString(rec.test_name).toHtmlEscaped())
                        .arg(rec.drones)
                        .arg(rec.times.empty() ? 0.0 : rec.times.back())
                        .arg(rec.log_interval));
  r->title->setToolTip(QString::fromStdString(rec.source.string()));
  r->title->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);  // a long name never widens the pane
  r->view = new SwarmView;
  r->view->set_options(options_);
  connect(r->view, &SwarmView::drone_clicked, this, [this](std::optional<std::uint32_t> id) { select(id); });
  auto* layout = new QVBoxLayout(r->pane);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(r->title);
  layout->addWidget(r->view, 1);

  if (run == 0) {  // Open: the only run, from the start, nothing selected
    for (auto& old : runs_) delete old->pane;
    runs_.clear();
    player_.pause();
    selected_.reset();
  } else if (runs_.size() > 1) {
    delete runs_[1]->pane;
    runs_.pop_back();
  }
  views_->addWidget(r->pane);
  runs_.push_back(std::move(r));
  views_->setSizes(QList<int>(views_->count(), 1000));  // the runs side by side at one size
  if (selected_ && *selected_ >= runs_.back()->recording->drones) selected_.reset();
  runs_changed();
  if (run == 0) player_.seek(0);
  show_time(player_.time(), true);
  Q_EMIT message(QString("replaying %1 (%2)").arg(folder, QString::fromStdString(runs_.back()->recording->source.filename().string())), false);
  return {};
}

void ReplayPage::runs_changed() {
  empty_->setVisible(runs_.empty());
  compare_->setEnabled(!runs_.empty());
  std::vector<double> times;
  for (const auto& r : runs_) times.insert(times.end(), r->recording->times.begin(), r->recording->times.end());
  player_.set_frames(std::move(times));
  {
    const QSignalBlocker quiet(timeline_);
    timeline_->setRange(0, static_cast<int>(std::lround(player_.end() * timeline_ticks)));
    timeline_->setSingleStep(timeline_ticks);
    timeline_->setPageStep(10 * timeline_ticks);
  }
  charts_->set_names(runs_.empty() ? QString() : QString::fromStdString(runs_[0]->recording->test_name),
                     runs_.size() > 1 ? QString::fromStdString(runs_[1]->recording->test_name) : QString());
  if (runs_.size() < 2) charts_->show_rows(nullptr, 1);
  for (auto& r : runs_) r->plotted.reset();
}

void ReplayPage::set_view_options(const ViewOptions& options) {
  options_ = options;
  for (auto& r : runs_) r->view->set_options(options);
}

void ReplayPage::select(std::optional<std::uint32_t> id) {
  selected_ = id;
  show_time(player_.time(), true);
}

void ReplayPage::show_time(double t, bool force) {
  {
    const QSignalBlocker quiet(timeline_);  // the playhead moved the slider, not the other way round
    timeline_->setValue(static_cast<int>(std::lround(t * timeline_ticks)));
  }
  clock_->setText(QString("t = %1 / %2 s").arg(t, 0, 'f', 1).arg(player_.end(), 0, 'f', 1));
  bool changed = false;
  for (auto& r : runs_) {
    const Recording& rec = *r->recording;
    if (rec.frames() == 0) continue;
    const std::size_t f = rec.frame_at(t);
    if (f == r->frame && !force) continue;
    r->frame = f;
    auto snap = std::make_shared<Snapshot>(recorded_snapshot(rec, r->scene, f, r->trail));
    if (selected_ && *selected_ < rec.drones && rec.status(f, *selected_) != 3) snap->selected = recorded_inspection(rec, f, *selected_);
    r->shown = std::move(snap);
    r->view->show_snapshot(r->shown);
    changed = true;
  }
  const qint64 now = QDateTime::currentMSecsSinceEpoch();
  if (changed && (!player_.playing() || now - charts_drawn_ >= charts_every_ms)) refresh_side_panels();
}

void ReplayPage::refresh_side_panels() {
  charts_drawn_ = QDateTime::currentMSecsSinceEpoch();
  QString text;
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    Run& r = *runs_[i];
    if (!r.shown) continue;
    // The rows up to the frame shown (a new object only when that count changed).
    const double t = r.shown->time;
    const auto end = std::upper_bound(r.stats.begin(), r.stats.end(), t, [](double v, const StatsRow& row) { return v < row.time; });
    if (!r.plotted || r.plotted->size() != static_cast<std::size_t>(end - r.stats.begin()))
      r.plotted = std::make_shared<const std::vector<StatsRow>>(r.stats.begin(), end);
    charts_->show_rows(r.plotted, static_cast<int>(i));
    if (r.shown->selected) {
      if (runs_.size() > 1) text += QString("%1%2, t = %3 s:\n").arg(text.isEmpty() ? "" : "\n\n").arg(QString::fromStdString(r.recording->test_name)).arg(t);
      text += inspection_text(*r.shown);
    }
  }
  if (text != inspector_->toPlainText()) inspector_->setPlainText(text);
}

}  // namespace salsa::gui
