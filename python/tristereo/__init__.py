"""tristereo: fixed-point stereo on a tritree mesh (Python bindings).

    import numpy as np, tristereo
    p = tristereo.Pipeline(640, 480, ndisp=64)
    out = p.process(left, right)      # uint8 arrays, (H, W) gray or (H, W, 3) RGB
    out.disparity                     # float32 pixels, NaN = invalid
    out.disp_q4                       # int16, disparity * 16, -32768 = invalid
    out.vertices, out.triangles, out.vertex_disp_q4, out.timings_ms

Errors of the library arrive as ValueError (bad input) or RuntimeError.
"""
from ._tristereo import (  # noqa: F401
    INVALID_DISP_Q4,
    Calibration,
    Output,
    Pipeline,
    VerifyReport,
    __version__,
    read_calibration,
    read_image,
    verify,
)
