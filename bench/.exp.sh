source .gpu/env.sh
W=1920; H=1080
VEIL_SHADER_DIR=$PWD/shaders veil-bench datasets/scenes/default.json --frames 400 --warmup 50 --width $W --height $H > /dev/null 2>&1
for rep in 1 2 3; do
for v in before after exp; do
  exe=veil-bench; sh=$PWD/shaders
  [ $v = before ] && exe=veil-bench-before sh=$GPU_FILES/shaders-before
  [ $v = exp ] && sh=$GPU_FILES/shaders-exp
  VEIL_SHADER_DIR=$sh $exe datasets/scenes/fog.json --oit blend --width $W --height $H --frames 120 --warmup 30 --json $OUT/x-$v-$rep.json > /dev/null 2>&1
  python3 -c "import json;d=json.load(open('$OUT/x-$v-$rep.json'));print('$v $rep', [ (p['name'], round(p['median_ms'],3)) for p in d['passes'] if p['name'] in ('fog','opaque')])"
done; done
