"""Serial bus servos (Dynamixel 1.0/2.0, Feetech): bus layer, safety guard, simulator, limits."""
