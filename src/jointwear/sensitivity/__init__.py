"""jointwear.sensitivity"""
