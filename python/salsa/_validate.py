"""salsa.validate: tests, queues and maps checked as `salsa validate` checks them, without running them."""

import json
import os

from . import _core


def validate(tests):
    """Checks tests as `salsa validate` does: each read as a run reads it, set up (its map built, its
    plugins given their data), and none run.

    tests: a test, queue or map file's path, a dict holding a test or a queue (as a file would), or a
    list of them. Returns the warnings (a test likely to take hours, a queue that sets a behavior with
    global shared state beside a radio: `salsa validate`'s "warning:" lines) as a list of strings, or
    None when there are none. Raises salsa.InputError with the CLI's
    line at the first bad input.
    """
    items = list(tests) if isinstance(tests, (list, tuple)) else [tests]
    if not items:
        raise ValueError("tests: an empty list (allowed: a file's path, a dict holding a test or a queue, or a list of them)")
    warnings = []
    for i, item in enumerate(items):
        where = "tests" if item is tests else f"tests[{i}]"
        if isinstance(item, dict):
            try:
                text = json.dumps(item)
            except (TypeError, ValueError) as e:
                raise TypeError(f"{where}: the dict holds a value JSON cannot hold: {e} "
                                "(allowed: dict, list, str, int, float, bool, None)") from None
            name = item.get("name")
            warnings += _core.validate_json(text, name if isinstance(name, str) and name else "test")
        elif isinstance(item, (str, os.PathLike)):
            warnings += _core.validate_file(os.fsdecode(item))
        else:
            raise TypeError(f"{where}: {type(item).__name__} (allowed: a file's path as str or os.PathLike, "
                            "or a dict holding a test or a queue)")
    return warnings or None
