// included by include_main.frag, from the same folder
float shade(float x) { return x * x; }
