#pragma once
// The inspector's text for the selected drone: who it is, then its state columns grouped by the model
// that keeps them (one line per column, a column a model adds shown without a line of the desktop's),
// then what is not a column (neighbours, obstacle hits, what it hears, its behavior's memory).
#include <QString>

#include "engine.hpp"

namespace salsa::gui {

/// The selected drone of `snap` as text (empty without a selection).
QString inspection_text(const Snapshot& snap);

}  // namespace salsa::gui
