# shellcheck shell=bash
# Bad input tried on the tristereo program: sourced by tests/cli/run_cases.sh,
# which defines $T (the program), $BAD (the hostile-file maker), $W (the work
# folder, the current folder of every case) and run():
#   run KIND EXIT REGEX DESCRIPTION COMMAND [AFTER_CHECK AFTER_DESCRIPTION]
# Add a case here, then regenerate the table of docs/reliability.md:
#   tests/cli/run_cases.sh build/tristereo build/tests/make_bad_files /tmp/cases --write-doc docs/reliability.md

# ---- fixtures (not cases): a 96x64 synthetic RGB pair, gray and hostile files
"$T" synth "$W/p" --width 96 --height 64 --ndisp 16 --seed 3 > /dev/null || exit 1
"$T" synth "$W/small" --width 40 --height 30 --ndisp 8 --seed 3 > /dev/null || exit 1
"$BAD" "$W" > /dev/null || exit 1
cp "$W/p/left.png" "$W/left_copy.png"
{ printf 'P6\n96 64\n255\n'; head -c 18432 /dev/zero | tr '\0' '\200'; } > "$W/rgb.ppm"
"$T" match "$W/p/left.png" "$W/p/right.png" --ndisp 16 --disp "$W/disp16.png" > /dev/null || exit 1
head -c 300 "$W/p/left.png" > "$W/truncated.png"
: > "$W/empty.png"
echo "left image" > "$W/text.png"
mkdir -p "$W/folder.png" "$W/folder.json"
printf 'P5\n16000 16000\n255\n0123456789' > "$W/claims_256M.pgm"
printf 'P5\n60000 60000\n255\n0123456789' > "$W/claims_3600M.pgm"
printf 'P5\n5000 2\n255\n' > "$W/wide.pgm"; head -c 10000 /dev/zero >> "$W/wide.pgm"
printf 'P5\n1 1\n255\nA' > "$W/dot.pgm"
{ printf 'P5\n8000 8000\n255\n'; head -c 64000000 /dev/zero; } > "$W/big_64M.pgm"
printf 'P5\n70000 1\n255\n' > "$W/too_wide.pgm"
printf 'P2\n2 2\n255\n0 1 2 300\n' > "$W/ascii_over_maxval.pgm"
printf 'P5\n2 2\n65535\n01234567' > "$W/maxval16.pgm"
echo "previous results" > "$W/old.csv"
echo "previous results" > "$W/old.ply"
echo "previous results" > "$W/old.pfm"
# /dev/full under an output name: a device node where root may create one
# (the reproducer), else a symbolic link to it.
mknod "$W/full.ply" c 1 7 2> /dev/null || ln -s /dev/full "$W/full.ply"
# All or nothing (issue 41): earlier outputs that existed must stay byte for
# byte what they were when the last output fails on a full device.
full() { mknod "$1" c 1 7 2> /dev/null || ln -s /dev/full "$1"; }
full "$W/full.json"
echo "previous disparities" > "$W/prev.pfm"; echo "previous mesh" > "$W/prev.ply"; echo "previous csv" > "$W/prev.csv"
cp "$W/prev.pfm" "$W/prev.pfm.orig"; cp "$W/prev.ply" "$W/prev.ply.orig"; cp "$W/prev.csv" "$W/prev.csv.orig"
mkdir -p "$W/sy" "$W/de" "$W/frames"
echo "previous left" > "$W/sy/left.png"; full "$W/sy/nonocc.png"
echo "previous left" > "$W/de/left.png"; full "$W/de/dense_stats.json"
# Frames of a --folder named like reports (the reader goes by content), and
# an image named like a report.
cp "$W/p/left.png" "$W/frames/left_0000.csv"; cp "$W/p/right.png" "$W/frames/right_0000.csv"
cp "$W/p/left.png" "$W/image.json"
# A Middlebury calibration for the 96x64 pair; one of absurd values (issue
# 41), one whose principal point is valid for a large image but not this one.
printf 'cam0=[200 0 48; 0 200 32; 0 0 1]\ndoffs=2\nbaseline=120\nwidth=96\nheight=64\n' > "$W/calib.txt"
printf 'cam0=[1e300 0 48; 0 1e300 32; 0 0 1]\ndoffs=2\nbaseline=1e300\n' > "$W/huge_f.txt"
printf 'cam0=[200 0 5000; 0 200 32; 0 0 1]\ndoffs=2\nbaseline=120\n' > "$W/far_cx.txt"
L=p/left.png
R=p/right.png
M="$T match $L $R"

# ---- usage errors: exit 2, the option named as typed
run error 2 '--ndisp 0 is out of range \[1, 256\]' "D = 0" "$M --ndisp 0"
run error 2 '--ndisp 0 is out of range \[1, 256\]' "D = 0 and a missing image: usage first" "$T match nope.png $R --ndisp 0"
run error 2 "--ndisp: 'sixty' is not an integer" "D not a number" "$M --ndisp sixty"
run error 2 '--ndisp 300 is out of range \[1, 256\]' "D > 256" "$M --ndisp 300"
run error 2 '--ndisp D is required' "no D" "$M"
run error 2 'option --ndisp needs a value' "option without its value" "$M --ndisp"
run error 2 'unknown option --nidsp' "misspelt option" "$M --nidsp 16"
run error 2 '--dmin -2147483648 is out of range' "d_min = INT_MIN" "$M --ndisp 16 --dmin -2147483648"
run error 2 '--dmin 99999999999 is out of range' "d_min beyond int" "$M --ndisp 16 --dmin 99999999999"
run error 2 '--dmin 5000 is out of range \[-2032, 2032\]' "d_min beyond the Q4 range" "$M --ndisp 16 --dmin 5000"
run error 2 '--window width 4 must be odd' "even window" "$M --ndisp 16 --window 4"
run error 2 '--window height 33 is out of range \[1, 31\]' "window too tall" "$M --ndisp 16 --window 5x33"
run error 2 '--psnr 5 is out of range \[10, 70\] dB' "PSNR threshold out of range" "$M --ndisp 16 --psnr 5"
run error 2 "--psnr: 'nan' is not a number" "PSNR threshold nan" "$M --ndisp 16 --psnr nan"
run error 2 '--max-area 0 is out of range' "maximum area 0" "$M --ndisp 16 --max-area 0"
run error 2 '--min-area 0 is out of range \[1, 32\]' "minimum area 0" "$M --ndisp 16 --min-area 0"
run error 2 '--max-area 3 is too small for the default minimum area of 2 px\^2 \(that needs --max-area >= 4\); add --min-area 1' \
  "maximum area too small for the default minimum area" "$M --ndisp 16 --max-area 3"
run error 2 '--min-area 2 is out of range \[1, 1\] \(at most half the largest power of two <= the maximum area, 3 px\^2\)' \
  "minimum area too large for the maximum area" "$M --ndisp 16 --max-area 3 --min-area 2"
run error 2 '--truncation 256 is out of range' "truncation 256" "$M --ndisp 16 --truncation 256"
run error 2 '--lambda -1 is out of range' "negative smoothness" "$M --ndisp 16 --lambda -1"
run error 2 '--gamma-color 0 is out of range' "adaptive weight scale 0" "$M --ndisp 16 --weights adaptive --gamma-color 0"
run error 2 "--weights: unknown weights 'gauss'" "unknown weights" "$M --ndisp 16 --weights gauss"
run error 2 "--gap: unknown gap policy 'sq'" "unknown gap policy" "$M --ndisp 16 --gap sq"
run error 2 "--kernels: unknown kernel set 'avx512'" "unknown kernel set" "$M --ndisp 16 --kernels avx512"
run error 2 '--threads must be 0' "threads > 256" "$M --ndisp 16 --threads 300"
run error 2 "--cpus: invalid CPU list '3-1'" "reversed CPU range" "$M --ndisp 16 --cpus 3-1"
run error 2 'match takes two image paths, LEFT and RIGHT; got 3' "three positional paths" "$M $L --ndisp 16"
run error 2 'match takes two image paths, LEFT and RIGHT; got 1' "one positional path" "$T match $L --ndisp 16"
run error 2 "unknown command 'mtach'" "misspelt command" "$T mtach $L $R"
run error 2 '--ndisp 0 is out of range' "verify with D = 0" "$T verify $L $R --ndisp 0"
run error 2 'verify takes two image paths, LEFT and RIGHT; got 3' "verify with three paths" "$T verify $L $R $R --ndisp 16"
run error 2 "--thread-counts: each count must be 1..256" "verify with 0 threads" "$T verify $L $R --ndisp 16 --thread-counts 1,0"
run error 2 "option --no-pin takes no value \(found '1'\)" "a flag given a value" "$M --ndisp 16 --no-pin=1"
run error 2 "--window: '3x' is not a size \(W or WxH" "window size cut short" "$M --ndisp 16 --window 3x"
run error 2 '--width 5 is out of range \[16, 4096\]' "synthetic scene too small" "$T synth s --width 5" "test ! -e s" "no folder s"
run error 2 '--ndisp 4 is out of range \[8, 256\]' "synthetic scene with D = 4" "$T synth s --ndisp 4"
run error 2 '--frame -1 is out of range \[0, 100000\]' "negative frame number" "$T synth s --frame -1"
run error 2 'synth needs OUTDIR' "synth without a folder" "$T synth"
run error 2 'synth takes one path, OUTDIR; got 2 \(a, b\)' "synth with two folders" "$T synth a b" \
  "test ! -e a && test ! -e b" "nothing written"
run error 1 "cannot create 'p/left.png': Not a directory" "synth into a file" "$T synth p/left.png"
run error 2 '--threads -1 is out of range \[0, 256\]' "demo with -1 threads" "$T demo d --threads -1" "test ! -e d" "nothing written"
run error 2 'demo takes at most one path, OUTDIR; got 2' "demo with two folders" "$T demo d e"
run error 2 "info takes no paths; got 'x'" "info with a path" "$T info x"
run error 2 '--max-size 0x0: the width 0 is out of range \[2, 4096\]' "info with an empty size" "$T info --max-size 0x0"
run error 2 '--ndisp 0 is out of range \[1, 256\]' "info with D = 0" "$T info --ndisp 0"
run error 2 '--realtime 0: real-time priority 0 is outside 1\.\.' "profile with real-time priority 0" \
  "$T profile --realtime 0 --frames 1"
run error 2 "--gpio: invalid GPIO line 'x'" "profile with a GPIO line that is no line" "$T profile --gpio x --frames 1"
run error 2 "--mesh m.obj: extension '.obj' is not written; the file must end in .ply" \
  "mesh in a format not written" "$M --ndisp 16 --mesh m.obj" "test ! -e m.obj" "no m.obj"
run error 2 "--disp-color c.jpg: extension '.jpg' is not written; the file must end in .png" \
  "colour map as JPEG" "$M --ndisp 16 --disp-color c.jpg" "test ! -e c.jpg" "no c.jpg"
run error 2 "--disp d.tiff: extension '.tiff' is not written; the file must end in .pfm, .png" \
  "disparity as TIFF" "$M --ndisp 16 --disp d.tiff"
run error 2 "--samples s: no extension; the file must end in .csv" "samples without extension" "$M --ndisp 16 --samples s"
run error 2 '--disp p/left.png is the LEFT input; refusing to overwrite an input' \
  "output over the LEFT input" "$M --ndisp 16 --disp $L --stats s.json" "cmp p/left.png left_copy.png && test ! -e s.json" \
  "LEFT unchanged, no other output written"
run error 2 '--disp-color ./p/../p/right.png is the RIGHT input' "output over RIGHT, by another path" \
  "$M --ndisp 16 --disp-color ./p/../p/right.png"
run error 2 '--points a.ply is also the --mesh output' "two outputs, one file" \
  "$M --ndisp 16 --camera 200,0.1,48,32 --mesh a.ply --points a.ply" "test ! -e a.ply" "nothing written"
run error 2 'option --stats given twice' "an option given twice" "$M --ndisp 16 --stats x.json --stats y.json"
run error 2 'option --dense given twice' "a flag given twice" "$M --ndisp 16 --dense --dense"
run error 2 'option --disp needs a value, but the option --stats follows it' "an output option missing its file" \
  "$M --ndisp 16 --disp --stats s.json" "test ! -e s.json" "nothing written"
run error 2 '--mesh-ascii has no effect without --mesh or --points' "ASCII without a PLY output" "$M --ndisp 16 --mesh-ascii"
run error 2 '--points-include-filled has no effect without --points or --mesh' "filled points without a PLY output" \
  "$M --ndisp 16 --points-include-filled --valid v.png" "test ! -e v.png" "nothing written"
run error 2 '--min-confidence 256 is out of range \[0, 255\]' "minimum confidence above 255" "$M --ndisp 16 --min-confidence 256"
run error 2 '--min-confidence -1 is out of range \[0, 255\]' "negative minimum confidence" "$M --ndisp 16 --min-confidence -1"
run error 2 "--min-confidence: 'high' is not an integer" "minimum confidence not a number" "$M --ndisp 16 --min-confidence high"
run error 2 "--valid v.pfm: extension '.pfm' is not written; the file must end in .png" "state map not a PNG" \
  "$M --ndisp 16 --valid v.pfm"
run error 2 "--confidence c.tif: extension '.tif' is not written; the file must end in .png" "confidence map not a PNG" \
  "$M --ndisp 16 --confidence c.tif"
run error 2 '--confidence vc.png is also the --valid output' "state and confidence into one file" \
  "$M --ndisp 16 --valid vc.png --confidence vc.png" "test ! -e vc.png" "nothing written"
run error 2 '--gamma-color has no effect without --weights adaptive' "adaptive weight scale with box weights" \
  "$M --ndisp 16 --gamma-color 5"
run error 2 '--support-trunc has no effect with --dense: the support prior works on the mesh' \
  "a support prior option with dense matching" "$M --ndisp 16 --dense --support-trunc 4 --disp d.pfm" \
  "test ! -e d.pfm" "nothing written"
run error 2 '--p1 has no effect with --optimizer dp: it is used only with --optimizer paths' \
  "a path penalty with the row DP" "$M --ndisp 16 --optimizer dp --p1 100"
run error 2 '--plane-tol has no effect with --support-prior 0 \(from --mode paper\)' \
  "a support prior option in the paper mode" "$M --ndisp 16 --mode paper --plane-tol 8"
run error 2 '--calib-unit mm has no effect: --calib calib.txt is a middlebury calibration' \
  "a unit for a Middlebury file (whose unit is fixed)" "$M --ndisp 16 --calib calib.txt --calib-unit mm --depth z.pfm" \
  "test ! -e z.pfm" "no z.pfm"
run error 2 '--calib-unit has no effect without --calib' "a calibration unit without a calibration" \
  "$M --ndisp 16 --camera 200,0.1,48,32 --calib-unit mm --depth z.pfm"
run error 2 '--left-pattern has no effect without --folder' "profile's frame pattern without a folder" \
  "$T profile --left-pattern l%d.png --frames 1"
run error 1 "cannot open '--left.png'" "after --, a path that starts with --" "$T match --ndisp 16 -- --left.png $R"
run error 2 '--disp d.png: a PNG cannot hold the negative disparities of --dmin -4' \
  "negative disparities into a PNG" "$M --ndisp 16 --dmin -4 --disp d.png"
run error 2 '--camera: focal length 1e\+308 px is outside \[1, 1e\+06\] px' "camera values that overflow" \
  "$M --ndisp 16 --camera 1e308,1e308,0,0 --mesh m.ply" "test ! -e m.ply" "no m.ply"
run error 2 '--camera: focal length 0 px is outside \[1, 1e\+06\] px' "zero focal length" "$M --ndisp 16 --camera 0,1,0,0 --mesh m.ply"
run error 2 '--camera: baseline 1e-300 m is outside \[0.0001, 1000\] m' "a baseline of 1e-300 (depth 0 m everywhere)" \
  "$M --ndisp 16 --camera 200,1e-300,48,32 --depth z.pfm" "test ! -e z.pfm" "no z.pfm"
run error 2 '--camera: principal point cy 1000 px is outside \[-64, 128\] px \(for a 96x64 image\)' \
  "principal point far outside the image" "$M --ndisp 16 --camera 200,0.1,48,1000 --depth z.pfm"
run error 2 '--camera: baseline 120 is taken as metres, and over 10 m is not a stereo rig.s: in millimetres it would be 0.12 m; write the unit \(e.g. 120mm or 0.12m\)' \
  "a baseline in millimetres without its unit" "$M --ndisp 16 --camera 200,120,48,32 --depth z.pfm" "test ! -e z.pfm" "no z.pfm"
run error 2 "--camera: baseline '120km' is not a number of metres, or one followed by m, cm or mm" "a baseline unit that is not m, cm or mm" "$M --ndisp 16 --camera 200,120km,48,32 --depth z.pfm"
run error 2 '--camera: baseline 120000 m is outside \[0.0001, 1000\] m' "a baseline over the bounds with its unit" \
  "$M --ndisp 16 --camera 200,120000m,48,32 --depth z.pfm"
run error 2 '--min-depth has no effect without --calib, --camera or --rig' "a depth limit without a camera" \
  "$M --ndisp 16 --min-depth 1 --mesh m.ply"
run error 2 '--max-depth has no effect without --depth, --points or --mesh' "a depth limit without a metric output" \
  "$M --ndisp 16 --camera 200,0.1,48,32 --max-depth 5"
run error 2 '--max-depth 1 must be above --min-depth 2' "depth limits the wrong way round" \
  "$M --ndisp 16 --camera 200,0.1,48,32 --min-depth 2 --max-depth 1 --depth z.pfm" "test ! -e z.pfm" "no z.pfm"
run error 2 '--min-disparity -1: expected a value >= 0' "a negative minimum disparity" \
  "$M --ndisp 16 --camera 200,0.1,48,32 --min-disparity -1 --depth z.pfm"
run error 2 "--max-depth: 'inf' is not a finite number" "an infinite depth limit" \
  "$M --ndisp 16 --camera 200,0.1,48,32 --max-depth inf --depth z.pfm"
run error 2 '--camera needs F,B,CX,CY' "camera with 3 numbers" "$M --ndisp 16 --camera 1,2,3 --mesh m.ply"
run error 2 '--calib and --camera both set the camera' "two cameras" "$M --ndisp 16 --camera 1,1,0,0 --calib x.txt"
run error 2 '--depth needs a camera' "depth without a camera" "$M --ndisp 16 --depth z.pfm"

# ---- bad input and failed checks: exit 1
run error 1 "cannot open 'nope.png': No such file or directory" "missing LEFT" "$T match nope.png $R --ndisp 16"
run error 1 "cannot read 'folder.png': it is a directory" "a folder as LEFT" "$T match folder.png $R --ndisp 16"
run error 1 "'empty.png' is empty" "empty file" "$T match empty.png $R --ndisp 16"
run error 1 "'text.png' is not a PNG or PGM/PPM file \(starts with \"left\"\)" "text file named .png" "$T match text.png $R --ndisp 16"
run error 1 "'/dev/zero' is not a PNG or PGM/PPM file" "endless stream of zeros (memory limit 100 MB)" \
  "vmem_limit_100mb; $T match /dev/zero $R --ndisp 16"
run error 1 "huge_claim.png': the header claims 16384 x 16384 pixels .* more than a 66-byte file can hold" \
  "66-byte PNG claiming 16384x16384 (memory limit 100 MB)" "vmem_limit_100mb; $T match huge_claim.png $R --ndisp 16"
run error 1 "palette_oob.png': pixel \(4, 0\) has palette index 5 but the palette has 2 entries" \
  "palette index beyond the palette" "$T match palette_oob.png $R --ndisp 16"
run error 1 "corrupt PNG 'truncated.png'" "PNG cut after 300 bytes" "$T match truncated.png $R --ndisp 16"
# Issue 41: libpng alone took 2.1 GB and 8-15 s on these 52 bytes; 2 s is plenty.
run error 1 "text_claim.png': chunk 'tEXt' at byte 33 claims 2147483632 bytes, but the 52-byte file ends 11 bytes" \
  "52-byte PNG whose tEXt claims 2^31-16 bytes (memory limit 100 MB, 2 s)" \
  "vmem_limit_100mb; timeout 2 $T match text_claim.png $R --ndisp 16"
run error 1 "iccp_claim.png': chunk 'iCCP' at byte 33 claims 2147483632 bytes" \
  "the same with an ICC profile, as a disparity file (memory limit 100 MB, 2 s)" \
  "vmem_limit_100mb; timeout 2 $T eval iccp_claim.png disp16.png"
run error 1 "corrupt PNM 'claims_256M.pgm': truncated: header promises 256000000 bytes of pixels, file has 10" \
  "PGM claiming 16000x16000 (memory limit 100 MB)" "vmem_limit_100mb; $T match claims_256M.pgm $R --ndisp 16"
run error 1 "PNM 'claims_3600M.pgm': image size 60000 x 60000 exceeds the reader limit of 268435456 pixels" \
  "PGM claiming 60000x60000" "$T match claims_3600M.pgm $R --ndisp 16"
# (Without the limit, under sanitizers, the size check answers instead.)
run error 1 "cannot read 'big_64M.pgm': not enough memory for it|the pair is 8000x8000" "a valid 64 MB image, 100 MB memory limit" \
  "vmem_limit_100mb; $T match big_64M.pgm big_64M.pgm --ndisp 16"
run error 1 "exceeds the reader limit of 65535 pixels per side" "PGM 70000 pixels wide" "$T match too_wide.pgm $R --ndisp 16"
run error 1 "sample 300 exceeds maxval 255" "ASCII PGM sample above maxval" "$T match ascii_over_maxval.pgm $R --ndisp 16"
run error 1 "has maxval 65535; only maxval 255" "16-bit PGM" "$T match maxval16.pgm $R --ndisp 16"
run error 1 "has bit depth 16; only 1, 2, 4 and 8-bit images are read here \(a 16-bit PNG is a disparity or depth map" \
  "a disparity PNG as LEFT" "$T match disp16.png $R --ndisp 16"
run error 1 "LEFT p/left.png is 96x64 but RIGHT small/right.png is 40x30" "images of different sizes" \
  "$T match $L small/right.png --ndisp 16"
run error 1 "the pair is 5000x2; matching takes 2 to 4096 pixels per side" "images wider than the pipeline takes" \
  "$T match wide.pgm wide.pgm --ndisp 16"
run error 1 "the pair is 1x1; matching takes 2 to 4096" "1x1 images" "$T match dot.pgm dot.pgm --ndisp 16"
run error 1 "calibration file 'missing.txt': cannot open it: No such file or directory" "missing calibration file" "$M --ndisp 16 --calib missing.txt"
run error 1 "calibration file '/dev/zero': more than 1048576 bytes, not a calibration file" \
  "endless stream as calibration (memory limit 100 MB)" "vmem_limit_100mb; $M --ndisp 16 --calib /dev/zero --depth z.pfm"
run error 1 "calibration file 'p': cannot read it" "a folder as calibration" "$M --ndisp 16 --calib p --depth z.pfm"
run error 1 "calibration file 'huge_f.txt', line 1, key 'focal length': focal length 1e\+300 px is outside \[1, 1e\+06\] px" \
  "calibration with f = B = 1e300 (+inf everywhere)" "$M --ndisp 16 --calib huge_f.txt --mesh m.ply" "test ! -e m.ply" "no m.ply"
run error 1 "calibration file 'far_cx.txt': principal point cx 5000 px is outside \[-96, 192\] px \(for a 96x64 image\)" \
  "calibration whose principal point is far outside the input" "$M --ndisp 16 --calib far_cx.txt --depth z.pfm"
run error 1 "--stats nodir/s.json: folder 'nodir': No such file or directory \(create it first\)" \
  "stats into a missing folder" "$M --ndisp 16 --disp d.pfm --stats nodir/s.json" "test ! -e d.pfm" "no d.pfm written"
run error 1 "--stats folder.json is a folder" "stats onto a folder" "$M --ndisp 16 --stats folder.json"
run error 1 "--mesh: cannot write 'full.ply': No space left on device" "mesh onto /dev/full (mknod full.ply c 1 7)" \
  "$M --ndisp 16 --mesh full.ply" "test -c full.ply" "full.ply still the device"
run error 1 "--samples: cannot write 'old.csv': File too large" "samples onto a full disk (ulimit -f 4)" \
  "ulimit -f 4; trap '' XFSZ; $M --ndisp 16 --samples old.csv" \
  "test \"\$(cat old.csv)\" = 'previous results' && test -z \"\$(ls -A | grep tmp-)\"" "old.csv intact, no temporary left"
run error 1 "--points: cannot write 'old.ply': File too large" "point cloud onto a full disk (ulimit -f 8)" \
  "ulimit -f 8; trap '' XFSZ; $M --ndisp 16 --camera 200,0.1,48,32 --points old.ply" \
  "test \"\$(cat old.ply)\" = 'previous results' && test -z \"\$(ls -A | grep tmp-)\"" "old.ply intact, no temporary left"
run error 1 "--disp: cannot write 'old.pfm': File too large" "disparity onto a full disk (ulimit -f 8)" \
  "ulimit -f 8; trap '' XFSZ; $M --ndisp 16 --disp old.pfm" \
  "test \"\$(cat old.pfm)\" = 'previous results' && test -z \"\$(ls -A | grep tmp-)\"" "old.pfm intact, no temporary left"

# ---- all or nothing: a failing output leaves every target as it was
nothing_new="cmp prev.pfm prev.pfm.orig && cmp prev.ply prev.ply.orig && cmp prev.csv prev.csv.orig && test -z \"\$(ls -A | grep -E 'tmp-|bak-')\""
run error 1 "--stats: cannot write 'full.json': No space left on device" \
  "match's last output onto /dev/full (mknod full.json c 1 7)" \
  "$M --ndisp 16 --disp prev.pfm --mesh prev.ply --samples prev.csv --disp-color new.png --stats full.json" \
  "$nothing_new && test ! -e new.png" "every earlier target byte-identical, no new file, no temporary"
run error 1 "OUTDIR: cannot write 'sy/nonocc.png': No space left on device" "synth whose last file is /dev/full" \
  "$T synth sy --width 32 --height 24 --ndisp 8" \
  "test \"\$(cat sy/left.png)\" = 'previous left' && test \"\$(ls -A sy | tr '\n' ' ')\" = 'left.png nonocc.png '" \
  "sy/left.png as it was, nothing else written"
run error 1 "OUTDIR: cannot write 'de/dense_stats.json': No space left on device" "demo whose last file is /dev/full" \
  "$T demo de --width 32 --height 24 --ndisp 8" \
  "test \"\$(cat de/left.png)\" = 'previous left' && test \"\$(ls -A de | tr '\n' ' ')\" = 'dense_stats.json left.png '" \
  "de/left.png as it was, nothing else written"
run error 1 "--json: cannot write 'full.json': No space left on device" "profile's --json onto /dev/full" \
  "$T profile --width 32 --height 24 --ndisp 8 --frames 2 --warmup 0 --csv prev.csv --json full.json" \
  "$nothing_new" "prev.csv as it was, no temporary"
run error 1 "--json: cannot write 'full.json': No space left on device" "eval's --json onto /dev/full" \
  "$T eval disp16.png disp16.png --disp-format q4 --gt-format q4 --json full.json" "test -c full.json || test -L full.json" "full.json still the device"
run error 2 "--csv frames/left_0000.csv is the frame 'frames/left_0000.csv' of --folder; refusing to overwrite an input" \
  "profile's report onto a frame of --folder" \
  "$T profile --folder frames --left-pattern left_%04d.csv --right-pattern right_%04d.csv --frames 1 --warmup 0 --csv frames/left_0000.csv" \
  "cmp frames/left_0000.csv p/left.png" "the frame unchanged"
run error 2 "--json image.json is the --left input; refusing to overwrite an input" "profile's report onto its input" \
  "$T profile --left image.json --right $R --frames 1 --json image.json" "cmp image.json p/left.png" "the input unchanged"
run error 2 "--json r.csv: extension '.csv' is not written; the file must end in .json" "profile's reports into one file" \
  "$T profile --frames 1 --csv r.csv --json r.csv" "test ! -e r.csv" "nothing written"

# ---- valid but suspicious: exit 0, a warning that says what to check
run warning 0 "warning: LEFT and RIGHT look swapped: .* check the order of the paths" "LEFT and RIGHT swapped" \
  "$T match $R $L --ndisp 16"
run warning 0 "warning: the disparity range 500..515 leaves no match inside the 96-pixel-wide image" \
  "--dmin 500 on a 96-wide pair" "$M --ndisp 16 --dmin 500"
run warning 0 "warning: the disparity range -200..-185 leaves no match" "range entirely below -W" "$M --ndisp 16 --dmin -200"
run warning 0 "warning: --threads [0-9]+ with only [0-9]+ CPUs allowed" "more threads than CPUs" "$M --ndisp 16 --threads \$((\$(nproc) + 1))"
run warning 0 "warning: --threads 2 with only 1 CPUs in --cpus" "more threads than --cpus" "$M --ndisp 16 --threads 2 --cpus 0"
run warning 0 "warning: --mesh m.ply: [0-9]+ of [0-9]+ faces left out; [0-9]+ touch a vertex without a valid disparity or one of the [0-9]+ vertices outside the depth limits \(d \+ doffs < --min-disparity 2 px, e.g. at or beyond infinity" \
  "metric mesh with vertices behind the camera" "$M --ndisp 16 --camera 100,1,48,32,-3 --mesh m.ply" "test -s m.ply" "m.ply written"
run warning 0 "warning: --camera: with doffs -20 px, no disparity searched \(0\.\.15\) gives a finite positive depth" \
  "a doffs that leaves no pixel a depth (without --mesh)" "$M --ndisp 16 --camera 200,0.1,48,32,-20 --depth z.pfm" \
  "test -s z.pfm" "z.pfm written"
run warning 0 "warning: --calib calib.txt: with doffs 2 px, no disparity searched \(-20\.\.-5\) gives" \
  "a disparity range with no depth, from a calibration file" "$M --ndisp 16 --dmin -20 --calib calib.txt --depth z.pfm"
run warning 0 "warning: LEFT p/left.png is gray but RIGHT rgb.ppm is RGB" "gray LEFT, RGB RIGHT" "$T match $L rgb.ppm --ndisp 16"
run warning 0 "warning: RIGHT p/right.png is gray but LEFT rgb.ppm is RGB" "RGB LEFT, gray RIGHT" "$T match rgb.ppm $R --ndisp 16"

# ---- raw cameras in (issue 38): --rig on match, rectify and info
rig_yaml() {  # rig_yaml WIDTH HEIGHT R-DATA: an OpenCV stereoCalibrate file
  printf '%%YAML:1.0\n---\nimage_width: %s\nimage_height: %s\n' "$1" "$2"
  for m in M1 M2; do printf '%s: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 90., 0., 48., 0., 90., 32., 0., 0., 1. ]\n' "$m"; done
  for d in D1 D2; do printf '%s: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ -0.05, 0., 0., 0., 0. ]\n' "$d"; done
  printf 'R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ %s ]\n' "$3"
  printf 'T: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ -0.1, 0., 0. ]\n'
}
rig_yaml 96 64 "1., 0., 0., 0., 1., 0., 0., 0., 1." > "$W/rig.yml"
rig_yaml 640 480 "1., 0., 0., 0., 1., 0., 0., 0., 1." > "$W/rig640.yml"
rig_yaml 96 64 "1., 0.3, 0., 0., 1., 0., 0., 0., 1." > "$W/rig_skewed.yml"
printf 'image_width: 96\nimage_height: 64\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [90, 0, 48, 0, 90, 32, 0, 0, 1]\n' > "$W/ros_left.yaml"
run error 2 "rectify needs --rig FILE" "rectify without a rig" "$T rectify $L $R --out-left a.png --out-right b.png"
run error 2 "rectify needs --out-right OUT.png" "rectify without its second output" "$T rectify $L $R --rig rig.yml --out-left a.png"
run error 2 "--out-left a.jpg" "rectify to a JPEG" "$T rectify $L $R --rig rig.yml --out-left a.jpg --out-right b.png"
run error 2 "--rig-right has no effect without --rig" "--rig-right alone" "$M --ndisp 16 --rig-right rig.yml"
run error 2 "--rig and --calib both give the camera" "--rig with --calib" "$M --ndisp 16 --rig rig.yml --calib calib.txt"
run error 1 "calibration file 'no_rig.yml': cannot open it" "missing rig file" "$M --ndisp 16 --rig no_rig.yml"
run error 1 "--rig rig640.yml is for 640x480 frames, the input is 96x64" "rig of another size" "$M --ndisp 16 --rig rig640.yml"
run error 1 "line 25, key 'R': is not a rotation" "rig whose R is not a rotation" "$T rectify $L $R --rig rig_skewed.yml --out-left a.png --out-right b.png" \
  "test ! -e a.png" "nothing written"
run error 1 "ROS camera_info file of one camera: the right camera's file is needed too" "one camera_info without --rig-right" \
  "$M --ndisp 16 --rig ros_left.yaml"
run error 1 "key 'distortion_model': missing" "camera_info pair without a distortion model" \
  "$M --ndisp 16 --rig ros_left.yaml --rig-right ros_left.yaml"

# ---- sequences in one run (issue 38): match --folder / --list
mkdir -p "$W/seq" "$W/seq_empty"
for i in 0 1 2; do cp "$W/p/left.png" "$W/seq/left_000$i.png"; cp "$W/p/right.png" "$W/seq/right_000$i.png"; done
cp "$W/truncated.png" "$W/seq/left_0001.png"
printf '# three words on a line\np/left.png p/right.png extra\n' > "$W/three_words.txt"
printf '# nothing but comments\n\n' > "$W/no_pairs.txt"
S="$T match --folder seq --ndisp 16"
run error 2 "--disp 'seqd.pfm' must contain exactly one %d-style field, found 0" "output of a sequence without a frame field" \
  "$S --disp seqd.pfm" "test ! -e seqd.pfm" "nothing written"
run error 2 "--mesh 'seqm_%d_%d.ply' must contain exactly one %d-style field, found 2" "output pattern with two fields" \
  "$S --mesh seqm_%d_%d.ply"
run error 2 "--samples 'seqs_%s.csv': only one %d-style field \(e.g. %04d\) is allowed" "output pattern with %s" \
  "$S --samples seqs_%s.csv"
run error 2 "--disp-color seq/left_0000.png is the LEFT input; refusing to overwrite an input" "output pattern onto the sequence's frames" \
  "$S --disp-color seq/left_%04d.png" "cmp seq/left_0000.png p/left.png" "the frame unchanged"
run error 2 "--stats seqstats.json: extension '.json' is not written; the file must end in .jsonl" "a sequence's --stats as .json" \
  "$S --stats seqstats.json"
run error 2 "--folder and --list both name the frames: give one" "--folder with --list" "$S --list no_pairs.txt"
run error 2 "--quiet has no effect without --folder or --list" "--quiet on one pair" "$M --ndisp 16 --quiet"
run error 2 "--reference is for one pair; it is not supported with --folder or --list" "--reference on a sequence" "$S --reference"
run error 1 "folder 'seq_empty' has no first frame: neither 'seq_empty/left_0000.png' nor 'seq_empty/left_0001.png' exists" \
  "empty sequence folder" "$T match --folder seq_empty --ndisp 16"
run error 1 "three_words.txt:2: expected two paths 'LEFT RIGHT', got 3 words" "--list line with three paths" \
  "$T match --list three_words.txt --ndisp 16"
run error 1 "list 'no_pairs.txt' holds no pair" "--list without a pair" "$T match --list no_pairs.txt --ndisp 16"
run error 1 "cannot open list 'no_list.txt'" "missing --list file" "$T match --list no_list.txt --ndisp 16"
run error 1 "frame 1 \(seq/left_0001.png, seq/right_0001.png\) skipped: error \(.*corrupt PNG" \
  "corrupt frame in the middle of a sequence" "$S --disp seqo_%d.pfm --quiet" \
  "test -s seqo_0.pfm && test -s seqo_2.pfm && test ! -e seqo_1.pfm" "frames 0 and 2 written, not 1"
