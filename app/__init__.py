"""trikecert: lateral stability certification of delta tricycle taxis."""
