"""tristereo: fixed-point stereo on a tritree mesh (Python bindings).

    import numpy as np, tristereo
    p = tristereo.Pipeline(640, 480, ndisp=64)   # keywords: the CLI's model options
    out = p.process(left, right)      # uint8 arrays, (H, W) gray
    out = p.process(l, r, order="bgr")  # (H, W, 3): say the order (OpenCV: "bgr")
    out.disparity                     # float32 pixels, NaN = invalid
    out.disp_q4                       # int16, disparity * 16, -32768 = invalid
    out.vertices, out.triangles, out.vertex_disp_q4, out.timings_ms
    out.uniqueness_rejected, out.lr_rejected, out.filled
    tristereo.depth(out.disp_q4, calib)          # metres, NaN = invalid
    tristereo.write_disparity("d.pfm", out.disp_q4)   # and the other files `match` writes

One Pipeline may be shared by threads (frames run one at a time, each caller
gets its own output); process() releases the GIL.

Errors arrive as ValueError (bad values), TypeError (values of the wrong type,
unknown keywords), OSError (unreadable files) or RuntimeError.
"""
from ._tristereo import (  # noqa: F401
    INVALID_DISP_Q4,
    Calibration,
    Output,
    Pipeline,
    VerifyReport,
    __version__,
    depth,
    model_options,
    read_calibration,
    read_image,
    verify,
    write_depth,
    write_disparity,
    write_disparity_color,
    write_mesh_ply,
    write_points_ply,
)
