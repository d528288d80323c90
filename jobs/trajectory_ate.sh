# Sourced by the tracking benchmarks: `ate EST REF` prints "2.59 cm (max 4.88)", the ATE of
# trajectory EST against REF by `$bin eval` ($bin set by the caller).
ate() {
  "$bin" eval --trajectory "$1" --reference "$2" --json |
    python3 -c 'import json, sys; j = json.load(sys.stdin); print("%.2f cm (max %.2f)" % (100 * j["ate_rmse"], 100 * j["ate_max"]))'
}
