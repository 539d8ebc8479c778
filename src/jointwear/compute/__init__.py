"""jointwear.compute"""
