#include "common.hpp"
class TestReliability : public QObject { Q_OBJECT };
QTEST_GUILESS_MAIN(TestReliability)
#include "test_reliability.moc"
