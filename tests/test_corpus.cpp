// The bad-input corpus (tests/corpus/README.md): every case runs the real salsa CLI in a fresh folder
// and must get its exit status, its one line naming the problem, and leave the folder around it as it
// was (every file hashed before and after), apart from the folders the case allows to change.
#include <QCryptographicHash>
#include <QDirIterator>
#include <QRegularExpression>
#include <QtTest>

#include "common.hpp"

using namespace salsa_test;

namespace {

struct Case {
  QStringList args, expect, changes;
  int exit = -1, lines = 1, timeout = 60;
  struct Plugin { QString source, dest; qint64 bytes = -1; };
  QList<Plugin> plugins;
  QList<QPair<QString, QString>> symlinks;  // link -> target
  QStringList dirs;
  QList<QPair<QString, QByteArray>> files;
  QList<QPair<QString, QString>> env;  // NAME=VALUE set for salsa
  QString error;  // a malformed case file
};

/// `{{repeat N TEXT}}` → TEXT written N times.
QByteArray expand(QByteArray text) {
  static const QRegularExpression repeat(R"(\{\{repeat (\d+) (.*?)\}\})");
  for (;;) {
    const auto m = repeat.match(QString::fromUtf8(text));
    if (!m.hasMatch()) return text;
    const QByteArray unit = m.captured(2).toUtf8();
    const QByteArray whole = m.captured(0).toUtf8();
    text.replace(text.indexOf(whole), whole.size(), unit.repeated(m.captured(1).toInt()));
  }
}

Case parse_case(const QString& path) {
  Case c;
  const QList<QByteArray> lines = read_file(path).split('\n');
  qsizetype i = 0;
  for (; i < lines.size() && !lines[i].startsWith("---"); ++i) {
    const QString line = QString::fromUtf8(lines[i]).trimmed();
    if (line.isEmpty() || line.startsWith('#')) continue;
    const qsizetype colon = line.indexOf(':');
    const QString key = line.left(colon), value = line.mid(colon + 1).trimmed();
    if (colon < 0) c.error = "no ':' in '" + line + "'";
    else if (key == "args") c.args = value.split(' ', Qt::SkipEmptyParts);
    else if (key == "exit") c.exit = value.toInt();
    else if (key == "expect") c.expect << value;
    else if (key == "lines") c.lines = value.toInt();
    else if (key == "timeout") c.timeout = value.toInt();
    else if (key == "changes") c.changes << value;
    else if (key == "mkdir") c.dirs << value;
    else if (key == "env") {
      const qsizetype eq = value.indexOf('=');
      if (eq <= 0) c.error = "env needs 'NAME=VALUE'";
      else c.env.append({value.left(eq), value.mid(eq + 1)});
    }
    else if (key == "symlink") {
      const QStringList parts = value.split(" -> ");
      if (parts.size() != 2) c.error = "symlink needs 'LINK -> TARGET'";
      else c.symlinks.append({parts[0], parts[1]});
    } else if (key == "plugin") {
      const QStringList parts = value.split(' ', Qt::SkipEmptyParts);
      if (parts.size() < 2 || parts.size() > 3) c.error = "plugin needs 'SRC DEST [BYTES]'";
      else c.plugins.append({parts[0], parts[1], parts.size() == 3 ? parts[2].toLongLong() : -1});
    } else c.error = "unknown key '" + key + "'";
  }
  while (i < lines.size()) {
    const QString name = QString::fromUtf8(lines[i].mid(3)).trimmed();
    QByteArrayList body;
    for (++i; i < lines.size() && !lines[i].startsWith("---"); ++i) body << lines[i];
    while (!body.isEmpty() && body.last().isEmpty()) body.removeLast();  // the file's end, not its text
    c.files.append({name, body.isEmpty() ? QByteArray() : expand(body.join('\n') + '\n')});
  }
  if (c.args.isEmpty()) c.error = "no args";
  if (c.exit < 0) c.error = "no exit status";
  return c;
}

QString source_plugin(const QString& source) {
  if (source.startsWith("test:")) return q(test_plugins_dir()) + "/" + source.mid(5);
  if (source.startsWith("builtin:")) return q(plugin_dir()) + "/" + source.mid(8);
  return {};
}

/// Every entry below `dir` (relative path → what it is: a file's hash, a link's target, "dir").
QMap<QString, QByteArray> tree(const QString& dir) {
  QMap<QString, QByteArray> out;
  QDirIterator it(dir, QDir::AllEntries | QDir::Hidden | QDir::System | QDir::NoDotAndDotDot, QDirIterator::Subdirectories);
  while (it.hasNext()) {
    const QString path = it.next();
    const QFileInfo info(path);
    QByteArray what;
    if (info.isSymLink()) what = "link " + info.symLinkTarget().toUtf8();
    else if (info.isDir()) what = "dir";
    else {
      QFile f(path);
      what = f.open(QIODevice::ReadOnly) ? QCryptographicHash::hash(f.readAll(), QCryptographicHash::Sha256).toHex()
                                         : QByteArray("unreadable");
    }
    out.insert(QDir(dir).relativeFilePath(path), what);
  }
  return out;
}

QMap<QString, QByteArray> without(QMap<QString, QByteArray> entries, const QStringList& changes) {
  for (const QString& c : changes)
    for (auto it = entries.begin(); it != entries.end();)
      it = it.key() == c || it.key().startsWith(c + "/") ? entries.erase(it) : std::next(it);
  return entries;
}

}  // namespace

class TestCorpus : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  void corpus_is_large() {
    QDirIterator it(q(source_dir() / "tests/corpus"), {"*.case"}, QDir::Files, QDirIterator::Subdirectories);
    int n = 0;
    while (it.hasNext()) it.next(), ++n;
    QVERIFY2(n >= 120, qPrintable(QString("the corpus holds %1 cases; at least 120 are required").arg(n)));
  }

  void bad_input_data() {
    QTest::addColumn<QString>("file");
    const QString root = q(source_dir() / "tests/corpus");
    QDirIterator it(root, {"*.case"}, QDir::Files, QDirIterator::Subdirectories);
    QStringList files;
    while (it.hasNext()) files << it.next();
    files.sort();
    for (const QString& f : files) QTest::newRow(qPrintable(QDir(root).relativeFilePath(f))) << f;
  }

  void bad_input() {
    QFETCH(QString, file);
    const Case c = parse_case(file);
    QVERIFY2(c.error.isEmpty(), qPrintable(file + ": " + c.error));

    QTemporaryDir tmp;
    QVERIFY(tmp.isValid());
    const QString dir = tmp.path();
    QVERIFY(QDir().mkpath(dir + "/home"));
    for (const QString& d : c.dirs) QVERIFY(QDir().mkpath(dir + "/" + d));
    for (const auto& [name, content] : c.files) QVERIFY2(write_file(dir + "/" + name, content), qPrintable(name));
    for (const auto& p : c.plugins) {
      QFile in(source_plugin(p.source));
      QVERIFY2(in.open(QIODevice::ReadOnly), qPrintable("no plugin " + p.source));
      QByteArray bytes = in.readAll();
      if (p.bytes >= 0) bytes.truncate(p.bytes);
      QVERIFY(write_file(dir + "/" + p.dest, bytes));
    }
    for (const auto& [link, target] : c.symlinks) {
      QDir().mkpath(QFileInfo(dir + "/" + link).absolutePath());
      QVERIFY(QFile::link(target, dir + "/" + link));
    }
    const auto before = tree(dir);

    QProcess p;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.remove("SALSA_PLUGIN_PATH");
    env.insert("HOME", dir + "/home");
    for (const auto& [name, value] : c.env) env.insert(name, value);
    p.setProcessEnvironment(env);
    p.setWorkingDirectory(dir);
    p.start(salsa_executable(), c.args);
    QVERIFY(p.waitForStarted(30000));
    const bool finished = p.waitForFinished(c.timeout * 1000);
    if (!finished) p.kill(), p.waitForFinished();
    CliResult r;
    r.crashed = p.exitStatus() != QProcess::NormalExit;
    r.exit_code = p.exitCode();
    r.out = QString::fromUtf8(p.readAllStandardOutput());
    r.err = QString::fromUtf8(p.readAllStandardError());
    QVERIFY2(finished, qPrintable("still running after " + QString::number(c.timeout) + " s\n" + describe(r)));
    QVERIFY2(!r.crashed, describe(r));
    QVERIFY2(r.exit_code == c.exit, describe(r));
    const QStringList lines = non_empty_lines(r.err);
    QVERIFY2(lines.size() == c.lines, describe(r));
    for (const QString& part : c.expect)
      QVERIFY2(r.err.contains(part), qPrintable("'" + part + "' missing from stderr\n" + describe(r)));

    const auto after = tree(dir);
    const auto kept = without(before, c.changes), now = without(after, c.changes);
    for (auto it = kept.begin(); it != kept.end(); ++it)
      QVERIFY2(now.value(it.key()) == it.value(), qPrintable(it.key() + " changed or vanished\n" + describe(r)));
    for (auto it = now.begin(); it != now.end(); ++it)
      QVERIFY2(kept.contains(it.key()), qPrintable(it.key() + " was created\n" + describe(r)));
  }
};

QTEST_GUILESS_MAIN(TestCorpus)
#include "test_corpus.moc"
