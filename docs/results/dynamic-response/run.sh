set -e
mkdir -p $OUT/dyn
C='default:;hysteresis 0.9:hysteresis=0.9;hysteresis 0.8:hysteresis=0.8;hysteresis 0.6:hysteresis=0.6;no management:classification=false,relocation_iterations=0'
A="--width 480 --height 270 --spp 1024 --warmup 64 --response-frames 200 --backend pipeline --pareto $OUT/dyn"
run() { deploy/gpu-run.sh ddgi-eval "$1" --dynamic "$2" --configs "$C" $A 2>&1 | grep -v "^$" | tee -a $OUT/dyn/log.txt; mkdir -p $OUT/dyn/$3 && mv $OUT/dyn/*.response.* $OUT/dyn/$3/; }
run scenes/cornell_box.gltf light:0:-0.7,-0.3,0 cornell-light
run scenes/cornell_box.gltf object:6:0,0,0.5 cornell-object
run scenes/two_rooms_open.gltf light:0:1.5,0,0 two-rooms-light
run scenes/veach_ajar.ddgi.json object:0:0,-0.5,0 veach-lamp
run scenes/modern_hall.ddgi.json object:19:0,-1,0 modern-hall-lamp
run scenes/living_room.ddgi.json object:37:0.5,0,0 living-room-sofa
run scenes/staircase.ddgi.json object:4:0,0,0.5 staircase-painting
cd $OUT/dyn && tar czf responses.tgz */ && rm -rf */
