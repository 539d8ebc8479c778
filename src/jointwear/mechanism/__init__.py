"""jointwear.mechanism"""
