# Shared by the bench/ scripts (source it): tools, timing, and COLMAP's front end run the one
# way every comparison uses it (CPU SIFT on one shared camera with the dataset's intrinsics,
# then exhaustive matching with its geometric verification).
# Expects: here (the checkout), optional PGBA / COLMAP from the environment.

COLMAP=${COLMAP:-colmap}
source "$here/bench/pgba_binary.sh"
command -v "$COLMAP" >/dev/null || { echo "error: colmap not found (apt-get install colmap, or set COLMAP=)" >&2; exit 2; }

now() { date +%s.%N; }
elapsed() { python3 -c "print(f'{$2 - $1:.2f}')"; }

# colmap_feature_extractor DATASET_DIR DB LOG [uncalibrated]: the dataset's first camera of
# cameras.txt as COLMAP's single camera (model and parameters), CPU SIFT with its defaults.
# With "uncalibrated": COLMAP's own prior instead (SIMPLE_RADIAL, EXIF focal or 1.2 max(w, h)).
colmap_feature_extractor() {
  local ds=$1 db=$2 log=$3 model params camera
  if [[ "${4:-}" == uncalibrated ]]; then
    camera=(--ImageReader.camera_model SIMPLE_RADIAL)
  else
    read -r model params < <(grep -v '^#' "$ds/cameras.txt" | awk 'NF {p=$5; for (i=6;i<=NF;i++) p=p","$i; print $2, p; exit}')
    camera=(--ImageReader.camera_model "$model" --ImageReader.camera_params "$params")
  fi
  "$COLMAP" feature_extractor --database_path "$db" --image_path "$ds/images" \
    --ImageReader.single_camera 1 "${camera[@]}" --SiftExtraction.use_gpu 0 >"$log" 2>&1
}

# colmap_exhaustive_matcher DB LOG (appends to LOG).
colmap_exhaustive_matcher() {
  "$COLMAP" exhaustive_matcher --database_path "$1" --SiftMatching.use_gpu 0 >>"$2" 2>&1
}
