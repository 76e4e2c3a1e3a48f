// Hashes for per-pixel decorrelation (PCG, Jarzynski & Olano 2020).
uint pcg_hash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

float hash_to_unit(uint v) { return float(pcg_hash(v) >> 8) * (1.0 / 16777216.0); }
