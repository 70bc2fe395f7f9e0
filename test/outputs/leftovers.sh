#!/bin/sh
# What an interrupted run leaves, and what reaches stdout:
#   - simulate --images: an image directory no dataset points at (a run killed between its images'
#     commit and its dataset's rename) is removed by the next run; a directory of that name that
#     holds something else than rendered images is kept; the truth is beside the dataset;
#   - import: a robot model identical to the one to write (an import stopped between the model and
#     the dataset) is no conflict; a different one is refused without --force, kept as it was;
#   - acquire on the simulated Viper850: stdout holds the tool's own line only (no ViSP text).
#   sh test/outputs/leftovers.sh APP WORK_DIR     (prints leftovers-ok)
set -u
APP="$1"; WORK="$2"
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 1
fail() { echo "FAILED: $*"; exit 1; }

"$APP" simulate ds.yaml --poses 3 --seed 2 --images > /dev/null 2>&1 || fail "simulate"
[ -s ds-truth.yaml ] || fail "no ds-truth.yaml"
first=$(ls -d ds-images-*) || fail "no image directory"
cp -r "$first" ds-images-0badc0de && mkdir ds-images-0000beef && cp "$first/0001.png" ds-images-0000beef/ &&
  echo keep > ds-images-0000beef/notes.txt || fail "setup"
"$APP" simulate ds.yaml --poses 3 --seed 3 --images --force > /dev/null 2>&1 || fail "simulate again"
[ -e ds-images-0badc0de ] && fail "the orphan image directory is still there"
[ -e "$first" ] && fail "the earlier run's images are still there"
[ -s ds-images-0000beef/notes.txt ] || fail "a directory holding another file was removed"
[ "$(ls -d ds-images-* | wc -l)" -eq 2 ] || fail "image directories: $(ls -d ds-images-*)"
grep -q "truth_of: ds.yaml" ds-truth.yaml || fail "truth"
echo "orphan images removed"

# A ViSP hand-eye folder of a robot without a preset (generic model written beside the dataset).
mkdir data || fail mkdir
for k in 1 2 3; do
  cp "$(ls -d ds-images-* | grep -v 0000beef)/000$k.png" data/arm_image-$k.png || fail "copy"
  printf 'rows: 6\ncols: 1\ndata:\n  - [0.%s]\n  - [0]\n  - [0.5]\n  - [0]\n  - [0]\n  - [0.%s]\n' $k $k > data/arm_pose_fPe_$k.yaml
done
printf '<?xml version="1.0"?>\n<root><camera><name>Camera</name><image_width>640</image_width><image_height>480</image_height><model><type>perspectiveProjWithoutDistortion</type><px>1500</px><py>1500</py><u0>320</u0><v0>240</v0></model></camera></root>\n' > data/arm_camera.xml
"$APP" import data --out imp.yaml > /dev/null || fail "import"
[ -s imp-robot.yaml ] || fail "no imp-robot.yaml"
rm imp.yaml
"$APP" import data --out imp.yaml > import2.txt || fail "import over the model it left"
grep -q "wrote imp.yaml and imp-robot.yaml" import2.txt || fail "second import: $(cat import2.txt)"
echo "# edited" >> imp-robot.yaml && cp imp-robot.yaml edited.yaml && rm imp.yaml
"$APP" import data --out imp.yaml > /dev/null 2> import3.txt
[ $? -eq 1 ] || fail "an edited model was replaced without --force"
grep -q "error: 'imp-robot.yaml' exists; use --force to replace it" import3.txt || fail "message: $(cat import3.txt)"
cmp -s imp-robot.yaml edited.yaml || fail "the edited model changed"
[ -e imp.yaml ] && fail "a dataset was written without its model"
echo "import pair ok"

"$APP" plan plan.txt --poses 6 --held-out 0 > /dev/null 2>&1 || fail "plan"
"$APP" acquire acq/ds.yaml --plan plan.txt > acquire.txt 2> /dev/null || fail "acquire"
[ "$(wc -l < acquire.txt)" -eq 1 ] && grep -q "^wrote acq/ds.yaml: " acquire.txt || fail "acquire's stdout: $(cat acquire.txt)"
[ "$(grep -c 'joints:' acq/ds.yaml)" -eq 6 ] || fail "acq/ds.yaml: $(grep -c 'joints:' acq/ds.yaml) poses, expected 6"
echo "acquire stdout ok"
echo "leftovers-ok"
