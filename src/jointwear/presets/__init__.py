"""jointwear.presets"""
