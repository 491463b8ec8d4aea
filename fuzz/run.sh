#!/usr/bin/env bash
# Runs every camloc fuzz target for a bounded time, seeded with the project's fixtures.
#   fuzz/run.sh [SECONDS_PER_TARGET] [TARGET...]      (default: 600 s, all targets)
# Needs cargo-fuzz (`cargo install cargo-fuzz`); RUSTC_BOOTSTRAP=1 lets the stable toolchain
# build with the sanitizer flags cargo-fuzz passes. Crashes are written to
# fuzz/artifacts/<target>/; turn each into a regression test before fixing it.
set -euo pipefail
cd "$(dirname "$0")"
seconds="${1:-600}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(bvh asf_amc keypoints keypoint_formats model basis dataset)
export RUSTC_BOOTSTRAP=1

seed() {
    local target=$1 dir=corpus/$1
    mkdir -p "$dir"
    case "$target" in
        bvh) cp ../fixtures/mocap/*.bvh "$dir"/ ;;
        asf_amc)
            # ASF, a NUL byte, then the AMC (the target's input layout).
            { cat ../fixtures/mocap/99.asf; printf '\0'; cat ../fixtures/mocap/99_01.amc; } > "$dir/99"
            ;;
        model | basis)
            # Both input layouts: the file as it is (selector 0) and its payload (selector 1).
            local file=../fixtures/default-$target.bin
            { printf '\0'; cat "$file"; } > "$dir/file"
            { printf '\1'; tail -c +29 "$file"; } > "$dir/payload"
            ;;
        dataset)
            # A small dataset made from the fixture mocap (xtask), whole and as a payload.
            local file=../target/fuzz-seed-dataset.bin
            [ -f "$file" ] || (cd .. && cargo xtask gen-dataset --mocap fixtures/mocap --stride 40 \
                --drop-landmarks 2 --protocol jittered --out target/fuzz-seed-dataset.bin)
            { printf '\0'; cat "$file"; } > "$dir/file"
            { printf '\1'; tail -c +29 "$file"; } > "$dir/payload"
            ;;
        keypoints)
            for f in ../fixtures/keypoints/*.json ../fixtures/keypoints/*.csv; do
                { printf '\3'; cat "$f"; } > "$dir/$(basename "$f")"
            done
            ;;
        keypoint_formats)
            # Byte 0: detect the format; byte 1: layout h36m17, min_score 0, read as bytes.
            for f in ../fixtures/keypoints/samples/*.* ../fixtures/keypoints/samples/openpose/*.json \
                     ../fixtures/keypoints/bad/npy_*.npy ../fixtures/keypoints/bad/[mo]*.json; do
                { printf '\5\1'; cat "$f"; } > "$dir/$(basename "$f")"
            done
            ;;
    esac
}

for target in "${targets[@]}"; do
    seed "$target"
    echo "== fuzzing $target for $seconds s"
    cargo fuzz run -O "$target" "corpus/$target" -- -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=65536
done
