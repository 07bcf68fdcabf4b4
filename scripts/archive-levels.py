#!/usr/bin/python3
"""docs/benchmarks.md's choice of the trajectory archive's deflate level: rewrites the state columns of
a trajectories.nc at each level with the archive's chunks and shuffle, and prints the file's size and
the time netCDF took to write it. Usage: scripts/archive-levels.py trajectories.nc [LEVEL...]"""
import os
import sys
import tempfile
import time

import netCDF4

source = netCDF4.Dataset(sys.argv[1])
source.set_auto_maskandscale(False)  # the stored values: packed millimetres stay integers
columns = [v for v in source.variables.values() if "salsa_model" in v.ncattrs()]
values = {v.name: v[...] for v in columns}
print(f"{len(columns)} columns, {sum(a.nbytes for a in values.values())} bytes of values")
for level in [int(a) for a in sys.argv[2:]] or [1, 2, 4, 6, 9]:
    with tempfile.TemporaryDirectory() as folder:
        file = os.path.join(folder, "levels.nc")
        start = time.perf_counter()
        out = netCDF4.Dataset(file, "w")
        out.set_auto_maskandscale(False)
        for name, size in source.dimensions.items():
            out.createDimension(name, None if size.isunlimited() else len(size))
        for v in columns:
            copy = out.createVariable(v.name, v.dtype, v.dimensions, zlib=True, complevel=level, shuffle=True,
                                      chunksizes=v.chunking(), fill_value=v.getncattr("_FillValue"))
            copy[...] = values[v.name]
        out.close()
        seconds = time.perf_counter() - start
        print(f"level {level}: {os.path.getsize(file)} bytes, written in {seconds:.2f} s")
