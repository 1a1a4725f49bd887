EXTRA_DIST += docs/modules.md docs/host-contract.md docs/scene.md docs/accuracy.md \
	docs/stages/gradient.md docs/stages/opacity_power.md docs/stages/boundary.md \
	docs/stages/silhouette.md docs/stages/orientation_fade.md docs/stages/sketch.md \
	docs/stages/tone_shading.md docs/stages/distance_blend.md docs/stages/distance_cue.md
